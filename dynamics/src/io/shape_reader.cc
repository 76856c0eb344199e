// The reader of "shapes" and "contact" (docs/contract.md, "Joint limits, contact and impacts"; docs/contact.md):
// each shape's body, type, dimensions, placement and law, every number bound to the field it lands in.
#include <array>

#include "scene_builder.h"

namespace tether::reading {
namespace {

using D = NumberDomain;

struct ShapeTypeKeys {
  const char* name;
  ShapeType type;
  std::set<std::string> dimensions;
};
const std::array<ShapeTypeKeys, 4> kShapeTypes = {{
    {"sphere", ShapeType::kSphere, {"radius"}},
    {"capsule", ShapeType::kCapsule, {"radius", "length"}},
    {"box", ShapeType::kBox, {"size"}},
    {"plane", ShapeType::kPlane, {}},
}};

const ShapeTypeKeys& TypeNamed(const Validator& check, const json& j, const std::string& at) {
  const std::string name = check.String(j, at);
  for (const ShapeTypeKeys& t : kShapeTypes) {
    if (name == t.name) return t;
  }
  check.Fail(at, "unknown shape type '" + name + "' (expected sphere, capsule, box or plane)");
}

}  // namespace

ContactMode SceneBuilder::ContactModeNamed(const json& j, const std::string& at) const {
  const std::string mode = check_.String(j, at);
  if (mode == "events") return ContactMode::kEvents;
  if (mode == "stepping") return ContactMode::kStepping;
  check_.Fail(at, "unknown contact mode '" + mode + "' (expected events or stepping)");
}

void SceneBuilder::ReadContact(const json& contact) {
  check_.Object(contact, "/contact", {"friction", "restitution", "exclude"});
  ContactSettings<double>& settings = model_.contact;
  if (const json* f = check_.Optional(contact, "friction")) {
    settings.friction = check_.NonNegative(*f, "/contact/friction");
    Bind(
        "/contact/friction", D::kNonNegative, [](auto& m) -> auto& { return m.contact.friction; });
  }
  if (const json* e = check_.Optional(contact, "restitution")) {
    settings.restitution = check_.NonNegative(*e, "/contact/restitution");
    if (!(settings.restitution <= 1.0)) {
      check_.Fail("/contact/restitution", "must be <= 1 (Newton's restitution), got " + Format(settings.restitution));
    }
    Bind(
        "/contact/restitution", D::kUnitInterval, [](auto& m) -> auto& { return m.contact.restitution; });
  }
  if (const json* exclude = check_.Optional(contact, "exclude")) {
    check_.Array(*exclude, "/contact/exclude");
    for (size_t i = 0; i < exclude->size(); ++i) {
      const std::string at = Child("/contact/exclude", i);
      const json& pair = check_.Array((*exclude)[i], at);
      if (pair.size() != 2) check_.Fail(at, "expected two body names, got " + std::to_string(pair.size()));
      const int a = BodyIndex(pair[0], Child(at, 0), true), b = BodyIndex(pair[1], Child(at, 1), true);
      if (a == b) check_.Fail(at, "the two bodies must differ");
      settings.exclude.emplace_back(a, b);
    }
  }
}

void SceneBuilder::ReadShapes(const json& shapes) {
  check_.Array(shapes, "/shapes");
  std::map<int, int> per_body;  // shapes so far on each body
  for (size_t i = 0; i < shapes.size(); ++i) {
    const std::string at = Child("/shapes", i);
    const json& s = shapes[i];
    if (!s.is_object()) check_.Fail(at, std::string("expected an object, got ") + TypeName(s));
    const ShapeTypeKeys& type = TypeNamed(check_, check_.Required(s, at, "type"), Child(at, "type"));
    std::set<std::string> keys = {"name", "body", "type", "position", "friction", "restitution", "contact"};
    keys.insert(Dim() == 3 ? "orientation" : "angle");
    keys.insert(type.dimensions.begin(), type.dimensions.end());
    check_.Object(s, at, keys);
    const int k = static_cast<int>(model_.shapes.size());
    Shape<double> shape;
    shape.scene_index = k;
    shape.type = type.type;
    shape.body = BodyIndex(check_.Required(s, at, "body"), Child(at, "body"), true);
    const std::string name = NewName(s, at, false);
    const std::string body_name = shape.body == kWorld ? "world" : model_.bodies[shape.body].name;
    shape.label = name.empty() ? body_name + "#" + std::to_string(per_body[shape.body]) : name;
    ++per_body[shape.body];
    if (const json* p = check_.Optional(s, "position")) {
      shape.position = check_.Vector(*p, Child(at, "position"), Dim());
      BindVector(
          Child(at, "position"), Dim(), D::kAny, [k](auto& m) -> auto& { return m.shapes[k].position; });
    }
    if (const json* o = Dim() == 3 ? check_.Optional(s, "orientation") : nullptr) {
      shape.orientation = Orientation(*o, Child(at, "orientation"));
      BindVector(
          Child(at, "orientation"), 4, D::kAny, [k](auto& m) -> auto& { return m.shapes[k].orientation; });
    }
    if (const json* a = Dim() == 2 ? check_.Optional(s, "angle") : nullptr) {
      shape.angle = check_.Number(*a, Child(at, "angle"));
      Bind(
          Child(at, "angle"), D::kAny, [k](auto& m) -> auto& { return m.shapes[k].angle; });
    }
    if (type.dimensions.count("radius")) {
      shape.radius = check_.Positive(check_.Required(s, at, "radius"), Child(at, "radius"));
      Bind(
          Child(at, "radius"), D::kPositive, [k](auto& m) -> auto& { return m.shapes[k].radius; });
    }
    if (type.dimensions.count("length")) {
      shape.length = check_.NonNegative(check_.Required(s, at, "length"), Child(at, "length"));
      Bind(
          Child(at, "length"), D::kNonNegative, [k](auto& m) -> auto& { return m.shapes[k].length; });
    }
    if (type.dimensions.count("size")) {
      const std::string sp = Child(at, "size");
      shape.size = check_.Vector(check_.Required(s, at, "size"), sp, Dim());
      for (int c = 0; c < Dim(); ++c) {
        if (!(shape.size[c] > 0)) check_.Fail(Child(sp, c), "must be > 0, got " + Format(shape.size[c]));
      }
      BindVector(
          sp, Dim(), D::kPositive, [k](auto& m) -> auto& { return m.shapes[k].size; });
    }
    if (const json* f = check_.Optional(s, "friction")) {
      shape.friction = check_.NonNegative(*f, Child(at, "friction"));
      shape.gives_friction = true;
      Bind(
          Child(at, "friction"), D::kNonNegative, [k](auto& m) -> auto& { return m.shapes[k].friction; });
    }
    if (const json* e = check_.Optional(s, "restitution")) {
      const std::string ep = Child(at, "restitution");
      shape.restitution = check_.NonNegative(*e, ep);
      if (!(shape.restitution <= 1.0)) {
        check_.Fail(ep, "must be <= 1 (Newton's restitution), got " + Format(shape.restitution));
      }
      shape.gives_restitution = true;
      Bind(
          ep, D::kUnitInterval, [k](auto& m) -> auto& { return m.shapes[k].restitution; });
    }
    if (const json* c = check_.Optional(s, "contact")) {
      if (!c->is_boolean())
        check_.Fail(Child(at, "contact"), std::string("expected true or false, got ") + TypeName(*c));
      shape.contact = c->get<bool>();
    }
    model_.shapes.push_back(shape);
  }
}

}  // namespace tether::reading
