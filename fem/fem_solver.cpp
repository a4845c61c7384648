#include "fem/fem_solver.hpp"

#include "fem/explicit_stage.hpp"
#include "fem/fem_model.hpp"
#include "fem/model_setup.hpp"

namespace slide::fem {

FemRunSummary run_fem(const FemPlan& plan, const Logger& log) {
  const FemSpec& fem = plan.source.fem;
  const FemModel model = make_model(plan.mesh, plan.source.materials, fem.kinematics,
                                    fem.hourglass_coefficient, plan.source.gravity, fem.water);
  ExplicitStage stage(plan, model, log);
  if (plan.run.inputs_only) return {};
  return stage.summary(run::execute(stage, plan.run, log));
}

}  // namespace slide::fem
