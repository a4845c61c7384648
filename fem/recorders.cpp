#include "fem/recorders.hpp"

#include <algorithm>
#include <array>
#include <limits>

#include <fmt/format.h>

#include "common/base/error.hpp"
#include "fem/pore_fluid.hpp"

namespace slide::fem {

namespace {

Index nearest_node(const FemModel& model, const Vec2& point) {
  Index best = 0;
  double distance = std::numeric_limits<double>::infinity();
  for (Index n = 0; n < model.node_count(); ++n) {
    const double d = (model.mesh.nodes[static_cast<std::size_t>(n)] - point).squaredNorm();
    if (d < distance) {
      distance = d;
      best = n;
    }
  }
  return best;
}

Index nearest_element(const FemModel& model, const Vec2& point) {
  Index best = 0;
  double distance = std::numeric_limits<double>::infinity();
  const int npe = model.nodes_per_element;
  for (Index e = 0; e < model.element_count(); ++e) {
    Vec2 centroid = Vec2::Zero();
    for (int k = 0; k < npe; ++k) {
      centroid += model.mesh.nodes[static_cast<std::size_t>(
          model.mesh.connectivity[static_cast<std::size_t>(e * npe + k)])];
    }
    const double d = (centroid / npe - point).squaredNorm();
    if (d < distance) {
      distance = d;
      best = e;
    }
  }
  return best;
}

/// The nodes of a recorder's node set, or Error naming the recorder.
std::vector<Index> node_set_nodes(const FemModel& model, const RecorderSpec& spec) {
  for (const NodeSet& set : model.mesh.node_sets) {
    if (set.name == spec.node_set) return set.nodes;
  }
  throw Error("fem.recorders \"{}\": the mesh has no node set \"{}\"", spec.name, spec.node_set);
}

/// The CSV header of a recorder's columns (without the line end).
std::string header(const std::vector<Index>& nodes, const std::vector<Index>& elements,
                   bool water) {
  std::string text = "time";
  if (!nodes.empty()) {
    for (const char* q : {"ux", "uy", "vx", "vy", "ax", "ay"}) text += fmt::format(",base_{}", q);
    for (const Index n : nodes) {
      for (const char* suffix : {"", "_rel"}) {
        for (const char* q : {"ux", "uy", "vx", "vy", "ax", "ay"}) {
          text += fmt::format(",n{}_{}{}", n, q, suffix);
        }
      }
      if (water) text += fmt::format(",n{}_p,n{}_dp", n, n);
    }
  }
  for (const Index e : elements) {
    for (const char* q : {"sxx", "syy", "szz", "sxy", "exx", "eyy", "ezz", "gxy"}) {
      text += fmt::format(",e{}_{}", e, q);
    }
    if (water) text += fmt::format(",e{}_p,e{}_ru", e, e);
  }
  return text;
}

/// Per element the means over its Gauss points of σ and ε, and with pore water p and r_u.
void append_elements(const FemModel& model, const FemState& state,
                     const std::vector<Index>& elements, run::RecorderFile& file) {
  const int n_gauss = model.gauss_per_element();
  for (const Index e : elements) {
    Vec4 stress = Vec4::Zero(), strain = Vec4::Zero();
    for (int g = 0; g < n_gauss; ++g) {
      const auto gp = static_cast<std::size_t>(e * n_gauss + g);
      stress += state.stress[gp];
      strain += state.strain[gp];
    }
    for (int i = 0; i < 4; ++i) file.add(stress[i] / n_gauss);
    for (int i = 0; i < 4; ++i) file.add(strain[i] / n_gauss);
    if (model.fluid.active()) {
      const auto [p, ratio] = element_pore_water(model, state, e);
      file.add(p);
      file.add(ratio);
    }
  }
}

/// The base's u, v, a, then per node its absolute and relative (to the base) u, v, a and
/// with pore water p and Δp.
void append_nodes(const FemModel& model, const FemState& state, const std::vector<Index>& nodes,
                  const std::array<Vec2, 3>& base, run::RecorderFile& file) {
  for (const Vec2& q : base) {
    file.add(q.x());
    file.add(q.y());
  }
  for (const Index node : nodes) {
    const auto n = static_cast<std::size_t>(node);
    const std::array<Vec2, 3> absolute{state.displacement[n], state.velocity[n],
                                       state.acceleration[n]};
    for (const Vec2& q : absolute) {
      file.add(q.x());
      file.add(q.y());
    }
    for (int i = 0; i < 3; ++i) {
      file.add(absolute[i].x() - base[i].x());
      file.add(absolute[i].y() - base[i].y());
    }
    if (model.fluid.active()) {
      file.add(state.pore_pressure[n]);
      file.add(state.pore_pressure[n] - state.static_pore_pressure[n]);
    }
  }
}

/// The drained faces whose two nodes are both in `nodes`.
std::vector<std::size_t> faces_of_set(const FemModel& model, const std::vector<Index>& nodes) {
  std::vector<std::uint8_t> in_set(static_cast<std::size_t>(model.node_count()), 0);
  for (const Index n : nodes) in_set[static_cast<std::size_t>(n)] = 1;
  std::vector<std::size_t> faces;
  for (std::size_t f = 0; f < model.fluid.faces.size(); ++f) {
    const auto& side = model.fluid.faces[f].side;
    if (side[0] >= 0 && in_set[static_cast<std::size_t>(side[0])] &&
        in_set[static_cast<std::size_t>(side[1])]) {
      faces.push_back(f);
    }
  }
  return faces;
}

}  // namespace

Recorders::Recorders(const FemModel& model, const std::vector<RecorderSpec>& specs,
                     std::filesystem::path folder, const GroundMotion* motion,
                     std::vector<Index> base_nodes)
    : model_(model),
      folder_(std::move(folder)),
      motion_(motion),
      base_nodes_(std::move(base_nodes)) {
  for (const RecorderSpec& spec : specs) {
    run::check_recorder_name(spec.name, "fem.recorders");
    Recorder r;
    for (const Vec2& p : spec.points) r.nodes.push_back(nearest_node(model, p));
    if (!spec.node_set.empty()) r.nodes = node_set_nodes(model, spec);
    for (const Vec2& p : spec.elements) r.elements.push_back(nearest_element(model, p));
    std::string columns = header(r.nodes, r.elements, model.fluid.active());
    if (!spec.node_set.empty() && model.fluid.active()) {
      r.drained_faces = faces_of_set(model, r.nodes);
      columns += ",outflow";
    }
    recorders_.push_back(std::move(r));
    files_.emplace_back(spec.name, std::move(columns), spec.every);
  }
}

void Recorders::bound(double duration, double step, std::size_t limit) {
  run::bound_recorders(files_, duration, step, "fem.recorders", limit);
}

void Recorders::resume(double time, const Logger& logger) {
  for (run::RecorderFile& file : files_) file.resume(folder_, time, logger);
}

void Recorders::record(const FemState& state, double dt) {
  const double t = state.time;
  if (std::ranges::none_of(files_, [&](const run::RecorderFile& f) { return f.due(t); })) return;
  // The base's fields as the nodes' are formed: u at t, v over the step, a at t − dt.
  std::array<Vec2, 3> base{Vec2::Zero(), Vec2::Zero(), Vec2::Zero()};
  if (motion_ != nullptr && dt > 0.0) {
    base = {motion_->displacement(t), motion_->step_velocity(t - dt, dt),
            motion_->acceleration(t - dt)};
  } else if (!base_nodes_.empty()) {
    for (const Index node : base_nodes_) {
      const auto n = static_cast<std::size_t>(node);
      base[0] += state.displacement[n];
      base[1] += state.velocity[n];
      base[2] += state.acceleration[n];
    }
    const double share = 1.0 / static_cast<double>(base_nodes_.size());
    for (Vec2& q : base) q *= share;
  }
  for (std::size_t k = 0; k < files_.size(); ++k) {
    run::RecorderFile& file = files_[k];
    const Recorder& r = recorders_[k];
    if (!file.due(t)) continue;
    file.begin_row(t);
    if (!r.nodes.empty()) append_nodes(model_, state, r.nodes, base, file);
    append_elements(model_, state, r.elements, file);
    if (r.drained_faces) {
      double outflow = 0.0;
      for (const std::size_t f : *r.drained_faces) {
        outflow += drained_outflow(model_, state, model_.fluid.faces[f]);
      }
      file.add(outflow);
    }
    file.end_row();
  }
}

void Recorders::write() const {
  for (const run::RecorderFile& file : files_) file.write(folder_);
}

std::string Recorders::describe() const {
  std::string text;
  for (std::size_t k = 0; k < files_.size(); ++k) {
    const run::RecorderFile& file = files_[k];
    if (!text.empty()) text += "; ";
    text +=
        fmt::format("{}: {} nodes, {} elements, {}", file.name(), recorders_[k].nodes.size(),
                    recorders_[k].elements.size(),
                    file.every() > 0.0 ? fmt::format("every {} s", file.every()) : "every step");
  }
  return text;
}

}  // namespace slide::fem
