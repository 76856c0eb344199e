// One descriptor per joint type: what tether knows of a joint, in one place. Its scene name and keys (read by
// the scene reader), the primitive parts its rows are made of (constraint_rows.h: BuildConstraintSet composes
// them, as Jolt's HingeConstraint composes a point part and a rotation part), its coordinates
// (joint_coordinates.h: CSV columns, motors, springs) and whether its coordinate takes a limit (unilateral_events.h:
// the limit's row is built from that coordinate's row). A joint type made of existing parts is one row of
// kJointKinds and its JointType; a joint with a new kind of row adds that part here and its rows in
// constraint_rows_impl.h.
//
//   type          parts (rows in 3D)                        coordinates                        limit
//   distance      distance (1)                              -                                  -
//   pin           point (d)                                 angle (2D, between planar bodies)  on the angle
//   slider        line (d - 1)                              -                                  -
//   hinge         point (3) + common axis (2)               angle                              on the angle
//   universal     point (3) + crossed axes (1)              -                                  -
//   prismatic     line (2) + frozen orientation (3)         displacement                       on the displacement
//   cylindrical   line (2) + common axis (2)                angle, displacement                -
//   weld          point (3) + frozen orientation (3)        -                                  -
//   double_hinge  two hinges in series through a massless link (4; constraint_rows.h)    -           -
//
//   distance      |p_B - p_A| = length
//   point         p_B = p_A (a revolute joint in 2D, a ball joint in 3D)
//   line          p_B on the line through p_A along `axis` (A's frame)
//   common axis   A's `axis` and B's image of it stay parallel
//   crossed axes  the angle between `axis` (A) and `axis_b` (B) as at the start
//   frozen orientation  the relative orientation of A and B as at the start
//   double hinge  A turns the link about `axis` through A's point, the link turns B about `axis_b` through B's
//                 point; the link's invariants as at the start
#pragma once

#include <string>
#include <string_view>

namespace tether {

enum class JointType { kDistance, kPin, kSlider, kHinge, kUniversal, kPrismatic, kCylindrical, kWeld, kDoubleHinge };

// The coordinates of a joint (CSV columns NAME.angle, NAME.omega; NAME.displacement, NAME.speed).
enum class JointCoordinate { kAngle, kDisplacement };

enum class JointPart { kNone, kDistance, kPoint, kLine, kCommonAxis, kCrossedAxes, kFrozenOrientation, kDoubleHinge };

// Which coordinates a joint type has; a planar angle is a 2D pin's, present only between planar rigid bodies
// (or one and the world).
enum class CoordinateSet { kNone, kAngle, kPlanarAngle, kDisplacement, kAngleAndDisplacement };

// The key that places a joint's axes, or sizes it: "axis" (required), "axes" (two, required) or "length"
// (optional, the initial distance by default).
enum class JointKey { kNone, kAxis, kAxes, kLength };

struct JointKind {
  JointType type;
  const char* name;  // the scene file's "type"
  bool spatial;      // needs dimension 3
  JointKey placing_key;
  CoordinateSet coordinates;  // the "angle" key sets an angle's value at the start
  bool limitable;             // takes "range" and "restitution" on its one coordinate
  JointPart parts[2];         // its rows, in this order; kNone ends the list
};

// one joint type, two lines
// clang-format off
inline constexpr JointKind kJointKinds[] = {
    {JointType::kDistance,    "distance",     false, JointKey::kLength, CoordinateSet::kNone,                 false,
     {JointPart::kDistance}},
    {JointType::kPin,         "pin",          false, JointKey::kNone,   CoordinateSet::kPlanarAngle,          true,
     {JointPart::kPoint}},
    {JointType::kSlider,      "slider",       false, JointKey::kAxis,   CoordinateSet::kNone,                 false,
     {JointPart::kLine}},
    {JointType::kHinge,       "hinge",        true,  JointKey::kAxis,   CoordinateSet::kAngle,                true,
     {JointPart::kPoint, JointPart::kCommonAxis}},
    {JointType::kUniversal,   "universal",    true,  JointKey::kAxes,   CoordinateSet::kNone,                 false,
     {JointPart::kPoint, JointPart::kCrossedAxes}},
    {JointType::kPrismatic,   "prismatic",    true,  JointKey::kAxis,   CoordinateSet::kDisplacement,         true,
     {JointPart::kLine, JointPart::kFrozenOrientation}},
    {JointType::kCylindrical, "cylindrical",  true,  JointKey::kAxis,   CoordinateSet::kAngleAndDisplacement, false,
     {JointPart::kLine, JointPart::kCommonAxis}},
    {JointType::kWeld,        "weld",         true,  JointKey::kNone,   CoordinateSet::kNone,                 false,
     {JointPart::kPoint, JointPart::kFrozenOrientation}},
    {JointType::kDoubleHinge, "double_hinge", true,  JointKey::kAxes,   CoordinateSet::kNone,                 false,
     {JointPart::kDoubleHinge}}};
// clang-format on

constexpr const JointKind& JointKindOf(JointType type) {
  for (const JointKind& kind : kJointKinds) {
    if (kind.type == type) return kind;
  }
  return kJointKinds[0];  // unreachable: every JointType is listed
}

// The kind the scene calls `name`, nullptr for none.
const JointKind* FindJointKind(std::string_view name);

// "distance, pin, ... or double_hinge": every type's name, for messages.
std::string JointTypeList();

// "hinge", "pin", ...: the scene file's name of a joint type.
inline const char* JointTypeName(JointType type) { return JointKindOf(type).name; }

constexpr bool HasAngle(const JointKind& kind) {
  return kind.coordinates == CoordinateSet::kAngle || kind.coordinates == CoordinateSet::kPlanarAngle ||
         kind.coordinates == CoordinateSet::kAngleAndDisplacement;
}

constexpr bool HasDisplacement(const JointKind& kind) {
  return kind.coordinates == CoordinateSet::kDisplacement || kind.coordinates == CoordinateSet::kAngleAndDisplacement;
}

// The coordinate a limitable joint's range bounds (its only one).
constexpr JointCoordinate LimitedCoordinate(const JointKind& kind) {
  return HasAngle(kind) ? JointCoordinate::kAngle : JointCoordinate::kDisplacement;
}

}  // namespace tether
