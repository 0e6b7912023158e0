#pragma once
// The particle shifting a case file chooses (docs/CASES.md, [fluid.shifting]).
#include <span>

#include "core/enum_names.hpp"

namespace isph {

enum class ShiftingType : int { none = 0, xu = 1, ops = 2 };
constexpr EnumName<ShiftingType> kShiftingTypeNames[] = {
    {ShiftingType::none, "none"}, {ShiftingType::xu, "xu"}, {ShiftingType::ops, "ops"}};
constexpr std::span<const EnumName<ShiftingType>> enum_names(ShiftingType) { return kShiftingTypeNames; }

// What the FSI shifting layer's Eq. 27 relocates (seed 001 §2.1.4; docs/VALIDATION.md section 26):
// literal: the shift of Eq. 21, as its text says; derived: the convection distance |u|_max dt, as its
// Eq. 28 substitutes it; relative: each particle's own convection distance past the structure.
enum class FsiLayerLaw : int { literal = 0, derived = 1, relative = 2 };
constexpr EnumName<FsiLayerLaw> kFsiLayerLawNames[] = {
    {FsiLayerLaw::literal, "literal"}, {FsiLayerLaw::derived, "derived"}, {FsiLayerLaw::relative, "relative"}};
constexpr std::span<const EnumName<FsiLayerLaw>> enum_names(FsiLayerLaw) { return kFsiLayerLawNames; }

}  // namespace isph
