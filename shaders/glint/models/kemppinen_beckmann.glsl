// The `kemppinen_beckmann` glint model: Kemppinen, Paulin, Thonat, Thiery,
// Lehtinen & Boubekeur 2025 with the Beckmann NDF instead of GGX, so that it
// is measured against the `grains` truth (whose mean is Beckmann with
// alpha_g) without a difference of distributions. Everything but the map of
// the half vector to the facets' square is glint/models/kemppinen.glsl; the
// map (x = (1 + erf(s)) / 2 of the stretched slope s per axis, which carries
// the Beckmann measure to the uniform one) and the facet lobe are described
// at the top of that file.
// glint_model truth=grains limit=beckmann checks=finite,unbiased,limit,deterministic
// glint_parameter filter_width default=0.7 range=0.1,4
// glint_parameter lod_offset default=true type=bool
// filter_width and lod_offset: as in glint/models/kemppinen.glsl.
#define KEMPPINEN_BECKMANN
#include "glint/models/kemppinen.glsl"
