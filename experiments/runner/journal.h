// The journal of a run: DIR/records.jsonl, one JSON line per finished
// record, appended and flushed to disk (fsync) as soon as the record exists.
// It is what makes a run resumable and shardable:
//   - line 1 is the run's header (experiment, its content hash, the options
//     that change results, the shard); a resume checks it matches;
//   - a run killed at any moment (SIGKILL included) leaves complete lines and
//     at most one torn last line, which is dropped when the journal is opened
//     again (the file is rewritten without it, atomically);
//   - frames.csv and summary.json are always written from the journal, so a
//     resumed run, a merged set of shards and an uninterrupted run produce the
//     same rows and the same metrics; a (variant, frame) is recorded once.
#pragma once

#include "experiments/runner/records.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace glintlab {

class Journal final : public RecordSink {
 public:
  // Opens DIR/records.jsonl. resume = false: a new journal with `header`
  // (an existing one is replaced; one of another command, `run`'s for `measure` or
  // the other way round, is a ConfigError naming the folder). resume = true: the existing journal is
  // loaded; its header must equal `header` (ConfigError naming what differs,
  // down to the input file that changed); a missing journal starts a new one.
  // The folder is locked (flock on DIR/.glintlab.lock) while the Journal
  // lives: a second run into the same folder is a ConfigError at once. The
  // lock file is removed when the Journal is destroyed (a killed process
  // leaves it, unlocked: the next run takes it).
  Journal(const std::filesystem::path& dir, const nlohmann::json& header, bool resume);
  ~Journal() override;
  Journal(Journal&& o) noexcept;
  Journal& operator=(Journal&&) = delete;

  // Loads a journal read-only (merge). Throws ConfigError for a missing file
  // or header.
  static Journal load(const std::filesystem::path& dir);

  const nlohmann::json& header() const { return header_; }
  bool has_frame(int variant, int frame) const { return frames_.count({variant, frame}) != 0; }
  const std::map<std::pair<int, int>, FrameRecord>& frames() const { return frames_; }
  const std::vector<ReferenceRecord>& references() const { return references_; }
  size_t dropped_lines() const { return dropped_; }

  void reference(const ReferenceRecord& r) override;
  void frame(const FrameRecord& r) override;

  // Hands every stored record to `sink` (references first, then frames by
  // variant and frame).
  void replay(RecordSink& sink) const;

  // Every stored record belongs to a run of this shape (a record of another
  // run, or a damaged index, is a ConfigError naming the line's record).
  void check_shape(int variants, int frames, int references) const;

  // The keys (dotted, one level into objects) where two headers differ.
  static std::string header_difference(const nlohmann::json& a, const nlohmann::json& b);

 private:
  Journal() = default;
  void read(const std::filesystem::path& path);
  void append(const nlohmann::json& line);
  void release_lock();  // removes DIR/.glintlab.lock and unlocks it

  std::filesystem::path path_;
  int fd_ = -1;
  int lock_fd_ = -1;
  nlohmann::json header_;
  std::map<std::pair<int, int>, FrameRecord> frames_;
  std::vector<ReferenceRecord> references_;
  std::set<std::pair<int, int>> reference_keys_;
  size_t dropped_ = 0;
};

}  // namespace glintlab
