// OpenSees → FE checkpoint (opensees2fem; tools/interop/README.md).
//
// The model (nodes, elements, materials, boundary sets) is the case's OpenSees mesh
// (mesh.generator = "opensees"); the state at one recorder time comes from the recorder
// files of the case's [opensees] table. What is made of them:
//  - reference coordinates: the model's node coordinates; displacement: the recorded one
//    minus the one of the first row at opensees.reference_time (the state fem-solve calls
//    u = 0: the end of the gravity stage) when the case gives it; x = X + u;
//  - velocity, acceleration (zero without a recorder), pore pressure (the u–p nodes' third
//    degree of freedom; zero without a recorder);
//  - Gauss-point stress: the recorded [σxx, σyy, σxy] (tension positive in both codes),
//    FourNodeQuad's points matched by place to this project's rule, and σzz = ν(σxx + σyy), the
//    plane-strain elastic relation (exact while the point is elastic);
//  - Gauss-point strain: the recorded [εxx, εyy, γxy] (engineering shear in both codes,
//    εzz = 0), minus the reference row's; without a strain recorder, the small-strain
//    B·u of the imported displacement;
//  - the plastic state is zero (OpenSees's recorders do not carry it), as are the hourglass
//    forces' history: a one-point quad gets the elastic K_q q of its displacement;
//  - the checkpoint's time is the recorder time minus opensees.start_time (0: the clock
//    that loadConst -time 0.0 reset at the start of the failure stage), its step 0.
#pragma once

#include "common/base/log.hpp"
#include "common/input/case_file.hpp"
#include "common/io/checkpoint.hpp"

namespace slide::interop {

/// The FE checkpoint of the case's OpenSees model at recorder time `time` (s, OpenSees's
/// clock). Throws Error (file, line, what) on any inconsistency between the model, the
/// case and the recorder files. `logger` (optional) gets what was read.
FemCheckpoint import_opensees(const Case& c, double time, const Logger* logger);

}  // namespace slide::interop
