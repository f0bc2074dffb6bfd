#include "experiments/runner/journal.h"

#include "core/util/atomic_file.h"
#include "core/util/io_error.h"
#include "core/util/json_check.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <set>
#include <sys/file.h>
#include <sys/stat.h>
#include <fstream>
#include <unistd.h>
#include <utility>

namespace fs = std::filesystem;

namespace glintlab {

namespace {
constexpr const char* kJournal = "records.jsonl";
constexpr const char* kLock = ".glintlab.lock";
// A line of the journal (dump_json: a string that is not UTF-8 does not fail the run).
std::string line_of(const nlohmann::json& j) { return dump_json(j) + "\n"; }

// Which command's outputs a journal header stands for: `measure`'s, or `run`'s (a render-only run too).
std::string owner_of(const nlohmann::json& header) {
  const auto c = header.find("command");
  return c != header.end() && *c == "measure" ? "measure" : "run";
}

// A journal that exists must be a regular file: opening a FIFO blocks until a writer comes (forever),
// and a folder or a device is no journal. ConfigError naming it.
void refuse_non_regular(const fs::path& journal) {
  std::error_code ec;
  const fs::file_status st = fs::status(journal, ec);
  if (ec || !fs::exists(st) || fs::is_regular_file(st)) return;
  const char* what = fs::is_directory(st) ? "a folder" : fs::is_fifo(st) ? "a FIFO" : "not a regular file";
  throw ConfigError(journal.string() + ": the run's journal is " + what +
                    "; glintlab reads and writes it as a regular file: remove it, or give another --out");
}

// A new journal must not replace another command's: its frames.csv, summary.json and images would
// be replaced in part and the rest left beside the new ones. ConfigError when `journal` (the first
// line) is a header of another command than `header`'s; nothing when there is no readable header.
void refuse_other_commands_folder(const fs::path& journal, const nlohmann::json& header) {
  std::ifstream in(journal);
  std::string line;
  if (!in || !std::getline(in, line)) return;
  const nlohmann::json old = nlohmann::json::parse(line, nullptr, false);
  if (!old.is_object() || !old.contains("type") || old["type"] != "run") return;
  const std::string was = owner_of(old), now = owner_of(header);
  if (was != now)
    throw ConfigError(journal.parent_path().string() + " holds the outputs of `" + was + "` (" + journal.string() +
                      "); `" + now + "` would mix its outputs with them: give another --out, or remove the folder");
}
}  // namespace

std::string Journal::header_difference(const nlohmann::json& a, const nlohmann::json& b) {
  std::string what;
  auto add = [&](const std::string& k) { what += (what.empty() ? "" : ", ") + k; };
  std::set<std::string> keys;
  for (auto it = a.begin(); it != a.end(); ++it) keys.insert(it.key());
  for (auto it = b.begin(); it != b.end(); ++it) keys.insert(it.key());
  for (const auto& k : keys) {
    const nlohmann::json va = a.contains(k) ? a[k] : nlohmann::json(), vb = b.contains(k) ? b[k] : nlohmann::json();
    if (va == vb) continue;
    if (va.is_object() && vb.is_object()) {  // name the entry: which input file changed
      std::set<std::string> sub;
      for (auto it = va.begin(); it != va.end(); ++it) sub.insert(it.key());
      for (auto it = vb.begin(); it != vb.end(); ++it) sub.insert(it.key());
      for (const auto& s : sub)
        if (!va.contains(s) || !vb.contains(s) || va[s] != vb[s]) add(k + "." + s);
    } else {
      add(k);
    }
  }
  return what;
}

void Journal::check_shape(int variants, int frames, int references) const {
  for (const auto& [key, r] : frames_)
    if (r.variant < 0 || r.variant >= variants || r.frame < 0 || r.frame >= frames)
      throw ConfigError(path_.string() + ": a frame record (variant " + std::to_string(r.variant) + ", frame " +
                        std::to_string(r.frame) + ") is outside this run (" + std::to_string(variants) +
                        " variants, " + std::to_string(frames) + " frames): the journal is of another run or damaged");
  for (const auto& r : references_)
    if (r.reference < 0 || r.reference >= references || r.frame < 0 || r.frame >= frames)
      throw ConfigError(path_.string() + ": a reference record (reference " + std::to_string(r.reference) +
                        ", frame " + std::to_string(r.frame) + ") is outside this run: the journal is of another "
                        "run or damaged");
}

Journal::Journal(const fs::path& dir, const nlohmann::json& header, bool resume) : path_(dir / kJournal) {
  // One writer per folder: the lock is held until this Journal is destroyed (or the process dies).
  // The lock file is removed when the lock is released, while it is still held: a writer that opened
  // it just before then locks a file no longer in the folder, sees that, and tries again.
  const fs::path lock = dir / kLock;
  for (int attempt = 0; lock_fd_ < 0; ++attempt) {
    lock_fd_ = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (lock_fd_ < 0) throw IoError(lock.string() + ": cannot open (" + std::strerror(errno) + ")");
    if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
      const int e = errno;
      ::close(lock_fd_);
      lock_fd_ = -1;
      if (e == EWOULDBLOCK)
        throw ConfigError(dir.string() + ": another glintlab run is writing this folder (it holds " + lock.string() +
                          "); wait for it to finish, or give another --out");
      throw IoError(lock.string() + ": cannot lock (" + std::strerror(e) + ")");
    }
    struct stat held {}, named {};
    if (::fstat(lock_fd_, &held) == 0 && ::stat(lock.c_str(), &named) == 0 && held.st_ino == named.st_ino &&
        held.st_dev == named.st_dev)
      break;
    ::close(lock_fd_);
    lock_fd_ = -1;
    if (attempt == 100) throw IoError(lock.string() + ": replaced while it was being locked, 100 times");
  }
  try {  // a constructor that throws runs no destructor: the lock is released here
    refuse_non_regular(path_);
    if (resume && fs::exists(path_)) {
      read(path_);
      if (header_ != header)
        throw ConfigError(path_.string() + ": --resume: this folder holds a run with other settings or inputs (" +
                          header_difference(header_, header) +
                          " differ); resume with the same experiment, options and files, or use a new --out");
      // Rewrite without a torn last line, so appends continue a clean file.
      std::string text = line_of(header_);
      for (const auto& r : references_) text += line_of(to_json(r));
      for (const auto& [key, r] : frames_) text += line_of(to_json(r));
      write_text_atomic(path_, text);
    } else {
      refuse_other_commands_folder(path_, header);
      header_ = header;
      write_text_atomic(path_, line_of(header_));
    }
  } catch (...) {
    release_lock();
    throw;
  }
  fd_ = ::open(path_.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
  if (fd_ < 0) {
    const int e = errno;
    release_lock();
    throw IoError(path_.string() + ": cannot open for appending (" + std::strerror(e) + ")");
  }
}

void Journal::release_lock() {
  if (lock_fd_ < 0) return;
  ::unlink((path_.parent_path() / kLock).c_str());  // still held: see the constructor
  ::close(lock_fd_);
  lock_fd_ = -1;
}

Journal::~Journal() {
  if (fd_ >= 0) ::close(fd_);
  release_lock();
}

Journal::Journal(Journal&& o) noexcept
    : path_(std::move(o.path_)), fd_(std::exchange(o.fd_, -1)), lock_fd_(std::exchange(o.lock_fd_, -1)),
      header_(std::move(o.header_)),
      frames_(std::move(o.frames_)), references_(std::move(o.references_)),
      reference_keys_(std::move(o.reference_keys_)), dropped_(o.dropped_) {}

Journal Journal::load(const fs::path& dir) {
  Journal j;
  j.path_ = dir / kJournal;
  if (!fs::exists(j.path_))
    throw ConfigError(j.path_.string() + ": no journal here (is " + dir.string() + " the --out of a glintlab run?)");
  refuse_non_regular(j.path_);
  j.read(j.path_);
  return j;
}

void Journal::read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  bool first = true;
  while (std::getline(in, line)) {
    const bool complete = !in.eof();  // a line without its newline was being written when the run stopped
    nlohmann::json j;
    try {
      if (!complete) throw std::invalid_argument("torn line");
      j = nlohmann::json::parse(line);
    } catch (const std::exception&) {
      ++dropped_;
      continue;
    }
    if (first) {
      first = false;
      if (!j.is_object() || !j.contains("type") || j["type"] != "run")
        throw ConfigError(path.string() + ": line 1 is not a glintlab run header");
      header_ = j;
      continue;
    }
    try {
      if (j.at("type") == "frame") {
        FrameRecord r = frame_record_from_json(j);
        frames_.emplace(std::make_pair(r.variant, r.frame), std::move(r));  // the first copy wins
      } else if (j.at("type") == "reference") {
        ReferenceRecord r = reference_record_from_json(j);
        if (reference_keys_.insert({r.reference, r.frame}).second) references_.push_back(r);
      }
    } catch (const std::exception&) {
      ++dropped_;
    }
  }
  if (first) throw ConfigError(path.string() + ": empty journal (no run header)");
}

void Journal::append(const nlohmann::json& line) {
  const std::string text = line_of(line);
  size_t done = 0;
  while (done < text.size()) {
    ssize_t n = ::write(fd_, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw IoError(path_.string() + ": cannot append (" + std::strerror(errno) + ")");
    done += size_t(n);
  }
  if (::fsync(fd_) != 0) throw IoError(path_.string() + ": cannot flush (" + std::strerror(errno) + ")");
}

void Journal::reference(const ReferenceRecord& r) {
  if (!reference_keys_.insert({r.reference, r.frame}).second) return;
  references_.push_back(r);
  references_.back().image = nullptr;
  append(to_json(r));
}

void Journal::frame(const FrameRecord& r) {
  if (has_frame(r.variant, r.frame)) return;
  FrameRecord stored = r;
  stored.image = nullptr;
  frames_.emplace(std::make_pair(r.variant, r.frame), stored);
  append(to_json(r));
}

void Journal::replay(RecordSink& sink) const {
  for (const auto& r : references_) sink.reference(r);
  for (const auto& [key, r] : frames_) sink.frame(r);
}

}  // namespace glintlab
