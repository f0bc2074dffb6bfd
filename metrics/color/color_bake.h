// OpenColorIO's answers for the shipped config, compiled into the program so that a short command need
// not load OpenColorIO to get them. Loading OpenColorIO and parsing a config (its YAML) is most of the
// start-up of `compare` on a small image pair, yet what a metric needs of the shipped config (the names
// of its spaces, and the conversions between its linear spaces: lin_rec709, ACEScg, ACES2065-1 to
// CIE-XYZ-D65 and back) is a table of names and single matrices.
//
// The build runs glintlab_ocio_bake (experiments/ocio_plugin/ocio_bake.cpp), which asks OpenColorIO,
// on metrics/color/ocio/config.ocio, for:
//   - the XXH3-128 of the config file's bytes;
//   - every name the config resolves (colour spaces, aliases, roles; lower case, as OpenColorIO looks
//     names up without regard to case) with its canonical space;
//   - every conversion between two of its spaces that OpenColorIO's optimised CPU processor renders as
//     nothing but matrix steps, with the steps as OpenColorIO holds them (double);
// and writes them as C++ (compiled_bake()). A ColorManager uses the bake only for a config file with the
// same bytes, and only while no OCIO_* environment variable is set (they change what OpenColorIO
// answers: active and inactive spaces, displays, views, optimisation). What the bake does not hold
// (curves, display transforms, listing the spaces) loads OpenColorIO as before.
//
// A baked conversion is computed as OpenColorIO's CPU renderers compute a matrix step, in single
// precision and in the same order, so its colours equal OpenColorIO's to the bit (the test
// ColorBake.ConversionsEqualOpenColorIOToTheBit checks every one on ordinary, extreme and non-finite
// values).
#pragma once

#include "core/util/ocio_plugin.h"

#include <cstddef>
#include <memory>
#include <string>

namespace glintlab::metrics {

struct BakedName {
  const char* name;       // lower case
  const char* canonical;  // the space's name
};
struct BakedConversion {
  const char* from;  // canonical names
  const char* to;
  const ocio::MatrixStep* steps;  // in order; none: the conversion changes nothing
  std::size_t step_count;
};
struct BakedConfig {
  const char* config_hash;  // XXH3-128 of the config file's bytes, 32 hex digits
  const BakedName* names;
  std::size_t name_count;
  const BakedConversion* conversions;
  std::size_t conversion_count;

  // The canonical name of `name` (any case), or nullptr where the config has no such name.
  const char* canonical(const std::string& name) const;
  // The conversion from one space to another (canonical names), or nullptr where it is not baked.
  const BakedConversion* conversion(const std::string& from, const std::string& to) const;
};

// The bake compiled into this program: the shipped config's, made at build time.
const BakedConfig& compiled_bake();

// compiled_bake() when the file at config_path has the bytes it was made from and no OCIO_* variable is
// set; nullptr otherwise (then OpenColorIO answers).
const BakedConfig* bake_for(const std::string& config_path);

// The lower-case key of a name, as BakedName holds it (ASCII, as OpenColorIO lowers names).
std::string bake_key(const std::string& name);

// A processor that applies a baked conversion's matrix steps as OpenColorIO's CPU renderers do.
std::shared_ptr<const ocio::Processor> baked_processor(const BakedConversion& conversion);

}  // namespace glintlab::metrics
