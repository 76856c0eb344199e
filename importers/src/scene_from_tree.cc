// SceneFromTree (import_model.h): links grouped into rigid bodies, joints mapped to constraints
// (joint_mapping.h), effects, markers and warnings, written as a tether scene.
//
// Mass properties of a body made of links i (a link and the links welded to it that merge into it):
//   m = sum m_i,  p_WC = sum m_i p_WCi / m,  I_C = sum R_WLi I_CLi R_WLi^T + m_i (|r_i|^2 1 - r_i r_i^T),
//   r_i = p_WCi - p_WC,  written in the body's axes (those of its first link): I_B = R_WB^T I_C R_WB.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>

#include "joint_mapping.h"
#include "placement.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/model/errors.h"
#include "tether/importers/import_model.h"

namespace tether::importers {
namespace {

using Eigen::Isometry3d;
using Eigen::Matrix3d;
using Eigen::Vector3d;
using json = nlohmann::ordered_json;

// An intermediate body of a split joint list weighs this fraction of the body it carries (mass and mean moment).
constexpr double kNegligible = 1e-6;

json Array3(const Vector3d& v) { return json::array({v[0], v[1], v[2]}); }

std::string Joined(const std::vector<const PlacedJoint*>& joints, const char* separator) {
  std::string out;
  for (const PlacedJoint* j : joints) out += (out.empty() ? "" : separator) + j->joint->name;
  return out;
}

// A tether body: a link with the links merged into it, or an intermediate body of a split joint list.
struct Body {
  std::string name;
  std::vector<int> links;                // the links it is made of, its own first (none: intermediate)
  double mass = 0.0;                     // kg
  Vector3d p_WC = Vector3d::Zero();      // centre of mass at the initial state
  Matrix3d R_WB = Matrix3d::Identity();  // its axes (its first link's) at the initial state
  Matrix3d I_C_W = Matrix3d::Zero();     // inertia about C in world axes
  Twist V;
  int parent = -1;                  // the body it hangs from (-1: the world)
  std::vector<PlacedJoint> joints;  // the model joints between parent and this body; none: welded
  bool fixed = false;               // --fix: part of the world instead
  bool removed = false;             // part of the world, or a massless link whose joints went to its only child
};

// How a model joint's coordinate lives on in the scene: a named constraint and which of its coordinates.
struct KeptCoordinate {
  std::string constraint;
  const char* coordinate = "angle";
  bool needs_key = false;  // a cylindrical joint has both coordinates, so effects must name one
};

class SceneBuilder {
 public:
  SceneBuilder(const KinematicTree& tree, const ImportOptions& options, const std::string& source)
      : tree_(tree), options_(options), source_(source) {}

  ImportedScene Build() {
    CheckJointFlags();
    placed_ = PlaceLinks(tree_, ToMap(options_.joint_values), ToMap(options_.joint_rates));
    reference_ = PlaceLinks(tree_, {}, {});
    GroupLinks();
    FixBodies();
    MergeFixedIntoWorld();
    CollapseMasslessLinks();
    for (Body& body : bodies_) {
      if (!body.removed) ComputeMassProperties(&body);
    }
    size_ = ModelSize();
    NameBodies();
    EmitConstraints();
    EmitEqualities();
    EmitMarkers();
    EmitShapes();
    EmitEffects();
    WarnAboutJoints();
    return Finish();
  }

 private:
  [[noreturn]] void Fail(const std::string& message) const { throw InputError(source_ + ": " + message); }

  std::map<std::string, double> ToMap(const std::vector<std::pair<std::string, double>>& list) const {
    std::map<std::string, double> map;
    for (const auto& [name, value] : list) map[name] = value;
    return map;
  }

  // --joint and --joint-velocity name hinges and slides of the model, each once.
  void CheckJointFlags() const {
    std::map<std::string, const TreeJoint*> joints;
    for (const TreeLink& link : tree_.links) {
      for (const TreeJoint& joint : link.joints) joints[joint.name] = &joint;
    }
    for (const auto* flag : {&options_.joint_values, &options_.joint_rates}) {
      const std::string name = flag == &options_.joint_values ? "--joint" : "--joint-velocity";
      std::set<std::string> seen;
      for (const auto& [joint, value] : *flag) {
        const auto it = joints.find(joint);
        if (it == joints.end()) throw InputError(name + " " + joint + ": the model has no joint named '" + joint + "'");
        if (it->second->type != TreeJointType::kHinge && it->second->type != TreeJointType::kSlide) {
          throw InputError(name + " " + joint + ": a ball or free joint has no single coordinate (hinges and " +
                           "slides have one)");
        }
        if (!seen.insert(joint).second) throw InputError(name + " " + joint + ": given twice");
        if (!std::isfinite(value)) throw InputError(name + " " + joint + ": the value must be finite");
      }
    }
  }

  // Links with joints are bodies; a link welded to a moving body is a body of its own (held by a weld) or merged
  // into that body (--merge-fixed, or when either is massless); links welded to the world are the world.
  void GroupLinks() {
    dropped_sites_ = tree_.world_sites;
    link_body_.assign(tree_.links.size(), -1);
    for (size_t i = 0; i < tree_.links.size(); ++i) {
      const TreeLink& link = tree_.links[i];
      const int parent = link.parent >= 0 ? link_body_[link.parent] : -1;
      if (link.static_link || (link.joints.empty() && parent < 0)) {
        for (const TreeSite& site : link.sites) dropped_sites_.push_back(site.name);
        continue;
      }
      if (link.joints.empty() && (options_.merge_fixed || link.mass <= 0 || LinkMass(bodies_[parent]) <= 0)) {
        bodies_[parent].links.push_back(static_cast<int>(i));
        link_body_[i] = parent;
        continue;
      }
      Body body;
      body.links = {static_cast<int>(i)};
      body.parent = parent;
      body.joints = placed_[i].joints;
      link_body_[i] = static_cast<int>(bodies_.size());
      bodies_.push_back(body);
    }
    if (bodies_.empty()) {
      Fail("nothing to import: the model has no moving body (every link is fixed to the world)");
    }
  }

  double LinkMass(const Body& body) const {
    double mass = 0.0;
    for (int link : body.links) mass += tree_.links[link].mass;
    return mass;
  }

  void FixBodies() {
    for (const std::string& name : options_.fixed_bodies) {
      int found = -1;
      for (size_t b = 0; b < bodies_.size(); ++b) {
        if (tree_.links[bodies_[b].links[0]].name == name) found = static_cast<int>(b);
      }
      if (found < 0) {
        throw InputError("--fix " + name + ": no moving body of " + source_ + " is named '" + name +
                         "' (a link welded to another one is part of that one's body)");
      }
      if (LinkMass(bodies_[found]) <= 0) {
        throw InputError("--fix " + name + ": the link '" + name + "' of " + source_ + " has no mass, so it is not " +
                         "a body to hold");
      }
      for (const PlacedJoint& joint : bodies_[found].joints) {
        for (const auto& [rate_of, rate] : options_.joint_rates) {
          if (rate_of == joint.joint->name) {
            throw InputError("--joint-velocity " + rate_of + ": the joint's body '" + name + "' is held by --fix");
          }
        }
      }
      bodies_[found].fixed = true;
    }
  }

  // A body held by --fix is part of the world, as links welded to the world are (and as MuJoCo has a body without
  // joints): its links and those welded to it become the world's, their geoms world shapes, their sites dropped,
  // and the bodies that hang from it by joints hang from the world at the same places. A weld of 6 rows would
  // have cost every step: the held body couples the rows of all the joints on it (a humanoid's torso, its four
  // limbs and its head). Bodies come after their parents, so one pass carries the world down the welds.
  void MergeFixedIntoWorld() {
    std::vector<char> in_world(bodies_.size(), 0);
    for (size_t b = 0; b < bodies_.size(); ++b) {
      Body& body = bodies_[b];
      const bool on_world = body.parent >= 0 && in_world[body.parent];
      if (body.removed || !(body.fixed || (on_world && body.joints.empty()))) {
        if (on_world) body.parent = -1;
        continue;
      }
      in_world[b] = 1;
      body.removed = true;
      for (const PlacedJoint& j : body.joints) replaced_.push_back(j.joint->name);
      for (int link : body.links) {
        link_body_[link] = -1;
        for (const TreeSite& site : tree_.links[link].sites) dropped_sites_.push_back(site.name);
      }
    }
    if (std::all_of(bodies_.begin(), bodies_.end(), [](const Body& body) { return body.removed; })) {
      Fail("nothing to import: --fix holds every moving body, so the model has none left");
    }
  }

  // A massless body that has joints cannot be a tether body. When it carries exactly one other body, by joints,
  // its joints join that body's (the chain of joints is then the child's); otherwise it weighs kNegligible of the
  // model's heaviest link.
  void CollapseMasslessLinks() {
    std::vector<std::string> collapsed, weighted;
    for (size_t b = 0; b < bodies_.size(); ++b) {
      Body& body = bodies_[b];
      if (LinkMass(body) > 0 || body.joints.empty() || body.fixed) continue;
      std::vector<int> children;
      for (size_t c = b + 1; c < bodies_.size(); ++c) {
        if (!bodies_[c].removed && bodies_[c].parent == static_cast<int>(b)) children.push_back(static_cast<int>(c));
      }
      if (children.size() == 1 && !bodies_[children[0]].joints.empty() && !bodies_[children[0]].fixed) {
        Body& child = bodies_[children[0]];
        child.joints.insert(child.joints.begin(), body.joints.begin(), body.joints.end());
        child.parent = body.parent;
        body.removed = true;
        for (int link : body.links) {
          link_body_[link] = -2;
          for (const TreeSite& site : tree_.links[link].sites) dropped_sites_.push_back(site.name);
        }
        collapsed.push_back(tree_.links[body.links[0]].name);
      } else {
        weighted.push_back(tree_.links[body.links[0]].name);
        negligible_links_.insert(body.links[0]);
      }
    }
    if (!collapsed.empty()) {
      warnings_.push_back(
          ListWarning("massless links with joints are not bodies: their joints join those of the "
                      "link they carry (exactly), and their sites are dropped",
                      collapsed));
    }
    if (!weighted.empty()) {
      for (const TreeLink& link : tree_.links) {
        heaviest_mass_ = std::max(heaviest_mass_, link.mass);
        largest_moment_ = std::max(largest_moment_, link.I_C_L.trace() / 2);  // a bound of the largest
      }
      warnings_.push_back(ListWarning("massless links with joints that carry no single link are given " +
                                          Format(kNegligible) + " of the heaviest link's mass and inertia (an error " +
                                          "of that order)",
                                      weighted));
    }
  }

  static std::string Format(double x) {
    std::ostringstream out;
    out << x;
    return out.str();
  }

  void ComputeMassProperties(Body* body) const {
    const PlacedLink& first = placed_[body->links[0]];
    body->R_WB = first.X_WL.linear();
    body->V = first.V_WL;
    std::vector<std::tuple<double, Vector3d, Matrix3d>> parts;
    for (int i : body->links) {
      const TreeLink& link = tree_.links[i];
      const Matrix3d& R = placed_[i].X_WL.linear();
      if (negligible_links_.count(i)) {
        parts.emplace_back(kNegligible * heaviest_mass_, placed_[i].X_WL * link.p_LC,
                           kNegligible * largest_moment_ * Matrix3d::Identity());
      } else {
        parts.emplace_back(link.mass, placed_[i].X_WL * link.p_LC, R * link.I_C_L * R.transpose());
      }
    }
    body->mass = 0.0;
    body->p_WC.setZero();
    for (const auto& [m, c, I] : parts) {
      body->mass += m;
      body->p_WC += m * c;
    }
    if (!(body->mass > 0.0) || !std::isfinite(body->mass)) {  // the centre of mass below would be 0/0
      Fail("link '" + tree_.links[body->links[0]].name + "': its mass is " + Format(body->mass) +
           " kg; a moving body needs a positive, finite mass");
    }
    body->p_WC /= body->mass;
    body->I_C_W.setZero();
    for (const auto& [m, c, I] : parts) {
      const Vector3d r = c - body->p_WC;
      body->I_C_W += I + m * (r.squaredNorm() * Matrix3d::Identity() - r * r.transpose());
    }
    CheckInertia(*body);
  }

  // tether's rigid bodies need positive principal moments (numerically: not below 1e-12 of the largest, where a
  // rotated zero is rounding), none above the sum of the other two.
  void CheckInertia(const Body& body) const {
    const Eigen::Vector3d moments = Eigen::SelfAdjointEigenSolver<Matrix3d>(body.I_C_W).eigenvalues();
    const std::string name = tree_.links[body.links[0]].name;
    const std::string values = Format(moments[0]) + ", " + Format(moments[1]) + ", " + Format(moments[2]);
    if (!(moments[0] > 1e-12 * moments[2])) {
      Fail("link '" + name + "': its principal moments of inertia (" + values + " kg m^2) must be positive in " +
           "tether, the smallest at least 1e-12 of the largest");
    }
    if (moments[2] > (moments[0] + moments[1]) * (1 + 1e-12)) {
      Fail("link '" + name + "': no rigid body has the principal moments " + values +
           " kg m^2 (the largest exceeds the sum of the other two)");
    }
  }

  // The largest distance of a link or joint from the world origin, for kSameLine.
  double ModelSize() const {
    double size = 0.0;
    for (const PlacedLink& link : placed_) {
      size = std::max(size, link.X_WL.translation().norm());
      for (const PlacedJoint& joint : link.joints) size = std::max(size, joint.p_WJ.norm());
    }
    return size;
  }

  // A name unique among bodies, constraints and markers (one namespace in a scene); a clash is renamed with a
  // suffix, and the rename noted.
  std::string Claim(const std::string& wanted, const std::string& suffix) {
    std::string name = wanted;
    for (int k = 1; name == "world" || names_.count(name); ++k) {
      name = wanted + "_" + suffix + (k > 1 ? std::to_string(k) : "");
    }
    names_.insert(name);
    if (name != wanted) renamed_.push_back(wanted + " -> " + name);
    return name;
  }

  void NameBodies() {
    for (Body& body : bodies_) {
      if (!body.removed) body.name = Claim(tree_.links[body.links[0]].name, "body");
    }
  }

  const std::string& BodyName(int body) const {
    static const std::string world = "world";
    return body < 0 ? world : bodies_[body].name;
  }

  // A world point or direction in a body's frame (origin at its centre of mass, its axes) at the initial state.
  Vector3d Local(int body, const Vector3d& p_W) const {
    if (body < 0) return p_W;
    return bodies_[body].R_WB.transpose() * (p_W - bodies_[body].p_WC);
  }
  Vector3d LocalDirection(int body, const Vector3d& u_W) const {
    return body < 0 ? u_W : Vector3d(bodies_[body].R_WB.transpose() * u_W);
  }

  void EmitWeld(int a, int b, const std::string& name) {
    json weld = {{"type", "weld"}};
    if (!name.empty()) weld["name"] = Claim(name, "weld");
    weld["bodies"] = {BodyName(a), BodyName(b)};
    weld["points"] = {Array3(Local(a, bodies_[b].p_WC)), Array3(Vector3d::Zero())};
    constraints_.push_back(weld);
  }

  // A joint's limits: its range, active. A start outside it is refused where --joint set it, and the limits left
  // out with a warning where the model starts there (MuJoCo's soft limits push such a joint back in).
  void AddLimits(const PlacedJoint& placed, json* constraint) {
    const TreeJoint& joint = *placed.joint;
    const Eigen::Vector2d& range = *joint.range;
    if (placed.value >= range[0] && placed.value <= range[1]) {
      (*constraint)["range"] = {range[0], range[1]};
      limits_kept_.push_back(joint.name);
      return;
    }
    for (const auto& [name, value] : options_.joint_values) {
      if (name != joint.name) continue;
      std::ostringstream out;
      out << "--joint " << name << "=" << value << ": outside the joint's range [" << range[0] << ", " << range[1]
          << "], which it keeps as a joint limit";
      throw InputError(out.str());
    }
    limits_outside_.push_back(joint.name);
  }

  void EmitConstraint(const ConstraintSpec& spec, int a, int b) {
    json c = {{"type", spec.type}, {"name", Claim(Joined(spec.joints, "+"), "joint")}};
    c["bodies"] = {BodyName(a), BodyName(b)};
    c["points"] = {Array3(Local(a, spec.p_WA)), Array3(Local(b, spec.p_WB))};
    if (spec.type == "universal" || spec.type == "double_hinge") {
      c["axes"] = {Array3(LocalDirection(a, spec.axis_A_W)), Array3(LocalDirection(b, spec.axis_B_W))};
    } else if (spec.type != "pin") {
      c["axis"] = Array3(LocalDirection(a, spec.axis_A_W));
    }
    if (spec.type == "hinge" || spec.type == "cylindrical") c["angle"] = spec.angle;
    const std::string name = c["name"];
    for (const PlacedJoint* joint : spec.joints) {
      const bool cylindrical = spec.type == "cylindrical";
      if (spec.type == "hinge" || (cylindrical && joint->joint->type == TreeJointType::kHinge)) {
        kept_[joint->joint->name] = {name, "angle", cylindrical};
      } else if (spec.type == "prismatic" || cylindrical) {
        kept_[joint->joint->name] = {name, "displacement", cylindrical};
      }
    }
    if ((spec.type == "hinge" || spec.type == "prismatic") && spec.joints[0]->joint->range)
      AddLimits(*spec.joints[0], &c);
    constraints_.push_back(c);
  }

  // Joints j_1..j_n between A and B, each its own constraint, through intermediate bodies K_1..K_{n-1}: K_k sits
  // where joint k leaves the link (frame F_k), weighs kNegligible of B, and is named after joint k.
  void EmitSplit(int a, int b) {
    const std::vector<PlacedJoint> joints = bodies_[b].joints;  // copies: bodies_ grows below
    const double mass = bodies_[b].mass, moment = bodies_[b].I_C_W.trace() / 3;
    int previous = a;
    for (size_t k = 0; k < joints.size(); ++k) {
      int next = b;
      if (k + 1 < joints.size()) {
        Body link;
        link.name = Claim(joints[k].joint->name + "_link", "body");
        link.mass = kNegligible * mass;
        link.I_C_W = kNegligible * moment * Matrix3d::Identity();
        link.p_WC = joints[k + 1].p_WJ;
        link.R_WB = joints[k].X_W_after.linear();
        link.V = joints[k].V_after;
        next = static_cast<int>(bodies_.size());
        bodies_.push_back(link);
        added_mass_ += link.mass;
      }
      if (const auto spec = SingleJointConstraint(joints[k])) EmitConstraint(*spec, previous, next);
      previous = next;
    }
    split_.push_back(BodyName(b) + " (" + Joined(Pointers(joints), ", ") + ")");
  }

  static std::vector<const PlacedJoint*> Pointers(const std::vector<PlacedJoint>& joints) {
    std::vector<const PlacedJoint*> out;
    for (const PlacedJoint& j : joints) out.push_back(&j);
    return out;
  }

  void EmitConstraints() {
    const size_t count = bodies_.size();  // EmitSplit appends intermediate bodies
    for (size_t i = 0; i < count; ++i) {
      const int b = static_cast<int>(i);
      const Body& body = bodies_[i];
      if (body.removed) continue;
      if (body.joints.empty()) {
        EmitWeld(body.parent, b, "");
      } else if (body.joints.size() == 1) {
        if (const auto spec = SingleJointConstraint(body.joints[0])) EmitConstraint(*spec, body.parent, b);
      } else if (const auto spec = options_.split_joints ? std::nullopt : CombinedConstraint(body.joints, size_)) {
        EmitConstraint(*spec, body.parent, b);
      } else {
        EmitSplit(body.parent, b);
      }
    }
    if (!replaced_.empty()) {
      warnings_.push_back(ListWarning("--fix makes bodies part of the world in place of their joints", replaced_));
    }
    if (!split_.empty()) {
      warnings_.push_back(ListWarning(
          "joints that no single tether constraint combines are split: each is its own constraint, joined by "
          "intermediate bodies of " +
              Format(kNegligible) + " of the carried body's mass and inertia (" + Format(added_mass_) +
              " kg added in all; measured on MuJoCo's humanoid split so, the bodies part " +
              "from MuJoCo's by 1.4e-7 m in 1 s: docs/import.md)",
          split_));
    }
  }

  // The body a link ended up in, or nullopt when it was collapsed away; -1 is the world.
  std::optional<int> BodyOfLink(int link) const {
    if (link < 0) return -1;
    if (link_body_[link] == -2) return std::nullopt;
    return link_body_[link];
  }

  // Connect and weld equalities, at the points of the reference configuration (MuJoCo's qpos0).
  void EmitEqualities() {
    std::vector<std::string> dropped;
    for (const TreeEquality& eq : tree_.equalities) {
      const std::optional<int> a = BodyOfLink(eq.link_1), b = BodyOfLink(eq.link_2);
      if (!a || !b || *a == *b) {
        dropped.push_back(eq.name);
        continue;
      }
      if (eq.type == TreeEquality::Type::kWeld) {
        EmitWeld(*a, *b, eq.name);
        continue;
      }
      const Vector3d p_W = eq.link_1 < 0 ? eq.p_L1 : Vector3d(reference_[eq.link_1].X_WL * eq.p_L1);
      json pin = {{"type", "pin"}, {"name", Claim(eq.name, "equality")}};
      pin["bodies"] = {BodyName(*a), BodyName(*b)};
      pin["points"] = {Array3(ReferenceLocal(*a, p_W)), Array3(ReferenceLocal(*b, p_W))};
      constraints_.push_back(pin);
    }
    if (!dropped.empty()) {
      warnings_.push_back(
          ListWarning("equality constraints between parts of one body, or on massless links, are "
                      "dropped",
                      dropped));
    }
  }

  // A world point of the reference configuration in a body's frame (the body's own frame does not depend on the
  // configuration: its centre of mass and axes are fixed in its first link).
  Vector3d ReferenceLocal(int body, const Vector3d& p_W) const {
    if (body < 0) return p_W;
    const int link = bodies_[body].links[0];
    const Isometry3d to_reference = reference_[link].X_WL * placed_[link].X_WL.inverse();
    return Local(body, to_reference.inverse() * p_W);
  }

  void EmitMarkers() {
    for (size_t b = 0; b < bodies_.size(); ++b) {
      const Body& body = bodies_[b];
      if (body.removed) continue;
      for (size_t k = 0; k < body.links.size(); ++k) {
        const int i = body.links[k];
        const TreeLink& link = tree_.links[i];
        if (k > 0) AddMarker(link.name, static_cast<int>(b), placed_[i].X_WL.translation());  // a merged frame
        for (const TreeSite& site : link.sites) AddMarker(site.name, static_cast<int>(b), placed_[i].X_WL * site.p_LS);
      }
    }
    if (!dropped_sites_.empty()) {
      warnings_.push_back(
          ListWarning("sites of the world, of static bodies and of massless links are dropped (a "
                      "marker names a point of a moving body)",
                      dropped_sites_));
    }
  }

  // The geoms as shapes, placed in their bodies' frames (a geom of a link welded to the world, of the world's); the
  // exclusions as body pairs. A geom of a massless link that collapsed away is dropped with a warning.
  void EmitShapes() {
    std::vector<std::string> dropped;
    for (const TreeGeom& geom : tree_.geoms) {
      const int body = geom.link >= 0 ? link_body_[geom.link] : -1;
      if (body == -2) {
        dropped.push_back(geom.name);
        continue;
      }
      const Isometry3d X_WL = geom.link >= 0 ? placed_[geom.link].X_WL : Isometry3d::Identity();
      const Matrix3d R_WB = body >= 0 ? bodies_[body].R_WB : Matrix3d(Matrix3d::Identity());
      const Matrix3d R_BS = R_WB.transpose() * X_WL.linear() * geom.q_LG.toRotationMatrix();
      Eigen::Quaterniond q(R_BS);
      q.normalize();
      if (q.w() < 0) q.coeffs() = -q.coeffs();
      json shape = {{"name", Claim(geom.name, "shape")}, {"body", BodyName(body)}};
      switch (geom.type) {
        case TreeGeom::Type::kSphere:
          shape["type"] = "sphere";
          shape["radius"] = geom.radius;
          break;
        case TreeGeom::Type::kCapsule:
          shape["type"] = "capsule";
          shape["radius"] = geom.radius;
          shape["length"] = geom.length;
          break;
        case TreeGeom::Type::kBox:
          shape["type"] = "box";
          shape["size"] = Array3(geom.size);
          break;
        case TreeGeom::Type::kPlane:
          shape["type"] = "plane";
          break;
      }
      shape["position"] = Array3(Local(body, X_WL * geom.p_LG));
      shape["orientation"] = {q.w(), q.x(), q.y(), q.z()};
      shape["friction"] = geom.friction;
      if (!geom.contact || !options_.contact) shape["contact"] = false;
      shapes_.push_back(shape);
    }
    std::set<std::pair<int, int>> excluded;
    for (const auto& [a, b] : options_.contact ? tree_.contact_excludes : std::vector<std::pair<int, int>>{}) {
      const int body_a = a >= 0 ? link_body_[a] : -1, body_b = b >= 0 ? link_body_[b] : -1;
      if (body_a == -2 || body_b == -2 || body_a == body_b) continue;
      excluded.insert({std::min(body_a, body_b), std::max(body_a, body_b)});
    }
    for (const auto& [a, b] : excluded) excludes_.push_back({BodyName(a), BodyName(b)});
    if (!dropped.empty()) {
      warnings_.push_back(ListWarning("collision shapes of massless links that collapsed away are dropped", dropped));
    }
  }

  void AddMarker(const std::string& name, int body, const Vector3d& p_W) {
    markers_.push_back(
        {{"name", Claim(name, "marker")}, {"body", BodyName(body)}, {"point", Array3(Local(body, p_W))}});
  }

  void EmitEffects() {
    if (!tree_.gravity.allFinite()) Fail("the model's gravity is not finite (a NaN or an infinity)");
    if (tree_.gravity.norm() > 0) effects_.push_back({{"type", "gravity"}, {"acceleration", Array3(tree_.gravity)}});
    for (const TreeLink& link : tree_.links) {
      for (const TreeJoint& joint : link.joints) {
        if (joint.stiffness == 0 && joint.damping == 0) continue;
        const auto it = kept_.find(joint.name);
        if (it == kept_.end()) {
          springs_dropped_.push_back(joint.name);
          continue;
        }
        json spring = {{"type", "joint_spring"}, {"joint", it->second.constraint}};
        if (it->second.needs_key) spring["coordinate"] = it->second.coordinate;
        spring["stiffness"] = joint.stiffness;
        spring["rest"] = joint.spring_rest;
        spring["damping"] = joint.damping;
        effects_.push_back(spring);
      }
    }
    for (const TreeMotor& motor : tree_.motors) {
      const auto it = kept_.find(motor.joint);
      if (it == kept_.end()) {
        motors_dropped_.push_back(motor.name == motor.joint ? motor.name : motor.name + " (on " + motor.joint + ")");
        continue;
      }
      json torque = {{"type", "joint_torque"}, {"joint", it->second.constraint}};
      if (it->second.needs_key) torque["coordinate"] = it->second.coordinate;
      torque["value"] = 0.0;
      effects_.push_back(torque);
    }
  }

  // One warning per kind of joint property that is dropped.
  void WarnAboutJoints() {
    std::vector<std::string> limits_dropped, armature, friction;
    for (const TreeLink& link : tree_.links) {
      for (const TreeJoint& joint : link.joints) {
        auto listed = [&joint](const std::vector<std::string>& names) {
          return std::find(names.begin(), names.end(), joint.name) != names.end();
        };
        const bool kept = listed(limits_kept_) || listed(limits_outside_);
        if (joint.range && !kept) limits_dropped.push_back(joint.name);
        if (joint.armature != 0) armature.push_back(joint.name);
        if (joint.friction_loss != 0) friction.push_back(joint.name);
      }
    }
    const std::string without =
        " of joints without a coordinate of their own in the scene (combined into one "
        "constraint, which --split-joints avoids, or replaced by --fix) are dropped";
    const std::vector<std::pair<std::string, const std::vector<std::string>*>> kinds = {
        {"limits" + without, &limits_dropped},
        {"limits of joints that start outside their range are dropped", &limits_outside_},
        {"stiffness and damping" + without, &springs_dropped_},
        {"motors" + without, &motors_dropped_},
        {"joint armature (rotor inertia) is dropped (tether has none)", &armature},
        {"joint friction loss (dry friction) is dropped (tether has none)", &friction},
        {"names already taken are given a suffix", &renamed_}};
    for (const auto& [what, names] : kinds) {
      if (!names->empty()) warnings_.push_back(ListWarning(what, *names));
    }
  }

  json BodyJson(const Body& body) const {
    json j = {{"name", body.name}, {"type", "rigid"}, {"mass", body.mass}};
    Matrix3d I_B = body.R_WB.transpose() * body.I_C_W * body.R_WB;
    I_B = (I_B + I_B.transpose()) / 2;
    const double off_diagonal = std::max({std::abs(I_B(0, 1)), std::abs(I_B(0, 2)), std::abs(I_B(1, 2))});
    if (off_diagonal <= 1e-15 * I_B.trace()) {
      j["inertia"] = Array3(I_B.diagonal());
    } else {
      j["inertia"] = {Array3(I_B.row(0)), Array3(I_B.row(1)), Array3(I_B.row(2))};
    }
    j["position"] = Array3(body.p_WC);
    Eigen::Quaterniond q(body.R_WB);
    q.normalize();
    if (q.w() < 0) q.coeffs() = -q.coeffs();
    j["orientation"] = {q.w(), q.x(), q.y(), q.z()};
    const Vector3d velocity = body.V.VelocityAt(body.p_WC);
    if (velocity.norm() > 0) j["velocity"] = Array3(velocity);
    if (body.V.w.norm() > 0) j["angular_velocity"] = Array3(body.V.w);
    return j;
  }

  ImportedScene Finish() {
    json bodies = json::array();
    for (const Body& body : bodies_) {
      if (!body.removed) bodies.push_back(BodyJson(body));
    }
    ImportedScene out;
    out.scene = {{"dimension", 3}, {"bodies", bodies}, {"constraints", constraints_}};
    if (!markers_.empty()) out.scene["markers"] = markers_;
    if (!shapes_.empty()) out.scene["shapes"] = shapes_;
    if (!excludes_.empty()) out.scene["contact"] = {{"exclude", excludes_}};
    out.scene["effects"] = effects_;
    if (tree_.time_step) out.scene["simulation"] = {{"step", *tree_.time_step}};
    out.warnings = tree_.warnings;
    out.warnings.insert(out.warnings.end(), warnings_.begin(), warnings_.end());
    std::string text;
    try {
      text = out.scene.dump();
    } catch (const nlohmann::json::type_error&) {  // MuJoCo and urdfdom take any bytes in a name
      throw InputError(source_ + ": a name in the model is not valid UTF-8, which a scene (JSON) cannot hold");
    }
    ParseScene(nlohmann::json::parse(text), source_ + " (imported)");
    return out;
  }

  const KinematicTree& tree_;
  const ImportOptions& options_;
  const std::string source_;
  std::vector<PlacedLink> placed_, reference_;
  std::vector<Body> bodies_;
  std::vector<int> link_body_;                         // the body of each link; -1 the world, -2 collapsed away
  std::set<int> negligible_links_;                     // massless links given kNegligible mass
  double heaviest_mass_ = 0.0, largest_moment_ = 0.0;  // over the links, for massless links given kNegligible
  double size_ = 0.0;
  double added_mass_ = 0.0;
  std::set<std::string> names_;
  std::map<std::string, KeptCoordinate> kept_;  // by model joint name
  json constraints_ = json::array(), markers_ = json::array(), effects_ = json::array();
  json shapes_ = json::array(), excludes_ = json::array();
  std::vector<std::string> warnings_, renamed_, split_, replaced_, dropped_sites_;
  std::vector<std::string> limits_kept_, limits_outside_, springs_dropped_, motors_dropped_;
};

}  // namespace

ImportedScene SceneFromTree(const KinematicTree& tree, const ImportOptions& options, const std::string& source) {
  return SceneBuilder(tree, options, source).Build();
}

}  // namespace tether::importers
