// The glint term of the sand (DESIGN "Ground truth"): which model shades the
// sparkles. One table of names; the numeric value is what the GPU sees
// (SandParamsGPU::glint_model = SAND_GLINT_* in shaders/sand/sand_params.glsl;
// a test checks that every row has its GLSL constant with the same value).
#pragma once

#include "core/util/named_enum.h"

#include <cstdint>

namespace glintlab::core {

enum class GlintModel : uint32_t {
  None = 0,      // no glint term
  Kajs = 1,      // Kajs 2022 eq. 4.17-4.23: per-grain cube micro normals, Gaussian gate
  Grains = 2,    // explicit microdetails at the glint density, point evaluation (the truth of zirr when supersampled)
  Zirr = 3,      // Zirr & Kaplanyan 2016: footprint-filtered binomial counting of reflecting microdetails
  Beckmann = 4,  // the smooth limit of grains and zirr: Cook-Torrance with the global Beckmann NDF
};

inline constexpr EnumTable<GlintModel, 5> kGlintModelNames{{
    {GlintModel::Kajs, "kajs"},
    {GlintModel::Grains, "grains"},
    {GlintModel::Zirr, "zirr"},
    {GlintModel::Beckmann, "beckmann"},
    {GlintModel::None, "none"},
}};

}  // namespace glintlab::core
