#pragma once
// The particle shifting a case file chooses (docs/CASES.md, [fluid.shifting]).
#include <span>

#include "core/enum_names.hpp"

namespace isph {

enum class ShiftingType : int { none = 0, xu = 1, ops = 2 };
constexpr EnumName<ShiftingType> kShiftingTypeNames[] = {
    {ShiftingType::none, "none"}, {ShiftingType::xu, "xu"}, {ShiftingType::ops, "ops"}};
constexpr std::span<const EnumName<ShiftingType>> enum_names(ShiftingType) { return kShiftingTypeNames; }

}  // namespace isph
