// What a resumed run does (experiments/runner/work_schedule.h): a rendered variant renders every frame
// up to its last missing one (its TAA history), a variant read from files reads only the frames it
// measures or records, and every measured frame's predecessor is measured again for the flicker
// tracker.
#include "experiments/runner/journal.h"
#include "experiments/runner/work_schedule.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace glintlab {
namespace {

std::string frames_of(const std::vector<char>& flags) {
  std::string s;
  for (char f : flags) s += f ? '1' : '.';
  return s;
}

TEST(WorkSchedule, FilesReadOnlyWhatIsMeasuredRendersRebuildTheirHistory) {
  test::TempDir dir("work_schedule");
  ExperimentSpec spec;
  spec.name = "schedule";
  VariantSpec rendered, read, alone;
  rendered.name = "taa";
  read.name = "files";
  alone.name = "alone";
  RunPlan plan;
  plan.spec = &spec;
  plan.frames = 6;
  plan.measure = true;
  for (const VariantSpec* v : {&rendered, &read, &alone}) {
    RunPlan::Variant pv;
    pv.spec = v;
    pv.reference = v == &alone ? -1 : 0;  // measured without a truth: its own flicker
    if (v != &rendered) pv.files = FrameFiles{};
    plan.variants.push_back(pv);
  }
  plan.references.push_back(RunPlan::Reference{"reference", {}, "", {0, 1}, std::nullopt});
  Journal journal(dir.path(), {{"type", "run"}}, false);
  for (int v = 0; v < 3; ++v)
    for (int k = 0; k < 3; ++k) {  // frames 0-2 done (a killed run)
      FrameRecord r;
      r.variant = v;
      r.frame = k;
      r.name = plan.variants[size_t(v)].spec->name;
      journal.frame(r);
    }

  const WorkSchedule w = schedule_work(plan, journal, 0, 6);
  EXPECT_EQ(w.last_frame, 5);
  EXPECT_EQ(frames_of(w.emit[0]), "...111");
  EXPECT_EQ(frames_of(w.emit[1]), "...111");
  EXPECT_EQ(frames_of(w.render[0]), "111111");  // TAA history from the first frame
  EXPECT_EQ(frames_of(w.render[1]), "..1111");  // files: the frame before the first missing, and on
  EXPECT_EQ(frames_of(w.render[2]), "..1111");
  for (int v = 0; v < 3; ++v) EXPECT_EQ(frames_of(w.measure[size_t(v)]), "..1111") << v;
  EXPECT_EQ(frames_of(w.reference[0]), "..1111");
  EXPECT_EQ(frames_of(w.motion), "..1111");
  EXPECT_EQ(w.emitted_frames(), 9u);

  // A shard of frames 4-5: the rendered variant still renders from frame 0, files read from frame 3.
  const WorkSchedule s = schedule_work(plan, journal, 4, 6);
  EXPECT_EQ(frames_of(s.emit[1]), "....11");
  EXPECT_EQ(frames_of(s.render[0]), "111111");
  EXPECT_EQ(frames_of(s.render[1]), "...111");
  EXPECT_EQ(frames_of(s.reference[0]), "...111");
}

}  // namespace
}  // namespace glintlab
