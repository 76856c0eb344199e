#include "tether/dynamics/io/scene_numbers.h"

namespace tether {

int SceneNumbers::Add(const std::string& pointer, NumberDomain domain, ModelField access,
                      std::optional<ScheduleKnot> knot, int field) {
  if (field < 0) field = fields_++;
  numbers_[pointer] = SceneNumber{field, domain, std::move(access), std::move(knot)};
  return field;
}

const SceneNumber* SceneNumbers::Find(const std::string& pointer) const {
  const auto it = numbers_.find(pointer);
  return it == numbers_.end() ? nullptr : &it->second;
}

std::vector<std::string> SceneNumbers::PointersOf(int field) const {
  std::vector<std::string> pointers;
  for (const auto& [pointer, number] : numbers_) {
    if (number.field == field) pointers.push_back(pointer);
  }
  return pointers;
}

}  // namespace tether
