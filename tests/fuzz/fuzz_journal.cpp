// libFuzzer harness: the journal reader of `--resume` and `merge` (glintlab::Journal: records.jsonl,
// torn lines, record parsing, the shape check against the run, the rewrite of a resumed journal).
//
// Input: the bytes of DIR/records.jsonl. Seeds: tests/fuzz/corpus/journal/.
//
// Oracle (anything else is a finding, see fuzz_common.h):
//   - Journal::load throws nothing but ConfigError (no header, not a run);
//   - check_shape(3 variants, 10 frames, 2 references) throws nothing but ConfigError;
//   - every record kept re-serialises to JSON that parses back to the same JSON (what a resumed run
//     rewrites is what it read);
//   - resuming into the folder with the journal's own header succeeds and keeps every record.

#include "core/util/json_check.h"
#include "experiments/runner/journal.h"
#include "tests/fuzz/fuzz_common.h"

#include <string>

using namespace glintlab_fuzz;

namespace {
std::string g_dir;
}

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  g_dir = make_temp_dir("journal");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 256 * 1024) return -1;
  write_file(g_dir + "/records.jsonl", data, size);
  try {
    glintlab::Journal j = glintlab::Journal::load(g_dir);
    try {
      j.check_shape(3, 10, 2);
    } catch (const glintlab::ConfigError&) {
    }
    for (const auto& [key, r] : j.frames()) {
      const nlohmann::json once = glintlab::to_json(r);
      const nlohmann::json twice = glintlab::to_json(glintlab::frame_record_from_json(once));
      if (once != twice) finding("journal-round-trip", once.dump() + " became " + twice.dump());
    }
    const size_t frames = j.frames().size(), references = j.references().size();
    const nlohmann::json header = j.header();
    {
      glintlab::Journal resumed(g_dir, header, /*resume=*/true);
      if (resumed.frames().size() != frames || resumed.references().size() != references)
        finding("journal-resume", "the resumed journal holds " + std::to_string(resumed.frames().size()) +
                                      " frame records, the loaded one " + std::to_string(frames));
    }
  } catch (const glintlab::ConfigError&) {
  } catch (...) {
    finding("journal-throws", current_exception_text());
  }
  return 0;
}
