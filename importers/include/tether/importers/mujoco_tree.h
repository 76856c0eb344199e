// MuJoCo's compiled model as a KinematicTree (kinematic_tree.h). Built only with MuJoCo (Debian's
// libmujoco-dev); ReadMjcf (import_model.h) is mj_loadXML followed by this.
//
// Read from mjModel, after MuJoCo's compiler has done its work (inertias inferred from geoms, angles in radians,
// defaults applied, frames composed): body_pos/body_quat (X_PL), body_mass, body_ipos/body_iquat/body_inertia
// (I_C_L = R_LI diag(body_inertia) R_LI^T), jnt_type/jnt_pos/jnt_axis, qpos0 (the reference), jnt_stiffness
// with qpos_spring, dof_damping, dof_armature, dof_frictionloss, jnt_range where jnt_limited, sites, motors
// (actuators on a joint with no dynamics, a fixed gain and no bias), connect and weld equalities, gravity and the
// time step. The option flags that disable gravity, passive forces, limits, equalities or contacts are honoured.
#pragma once

#include <mujoco/mujoco.h>

#include "tether/importers/kinematic_tree.h"

namespace tether::importers {

KinematicTree TreeFromMujoco(const mjModel& model);

}  // namespace tether::importers
