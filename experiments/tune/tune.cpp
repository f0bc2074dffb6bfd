#include "experiments/tune/tune.h"
#include "core/util/strings.h"

#include "experiments/runner/schema.h"

#include "core/util/atomic_file.h"
#include "core/util/data_dir.h"
#include "core/util/json_check.h"
#include "experiments/cli/exit_codes.h"
#include "experiments/runner/schema.h"
#include "experiments/spec/experiment_spec.h"
#include "metrics/metric_registry.h"

#include <sys/file.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <regex>

extern char** environ;

namespace glintlab {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// What a study may minimise: gpu_ms and every metric whose best value is its lowest ("min") or 1 (a
// ratio, scored as |ln ratio|), from the metric table (metrics/metric_registry.h); not psnr (maximised,
// unbounded where the test equals the truth), the counts of defects, the motion check or the pooled
// kinds by block size.
const std::vector<std::string>& objectives() {
  static const std::vector<std::string> out = [] {
    std::vector<std::string> o = {"gpu_ms"};
    for (const metrics::MetricInfo& m : metrics::metric_table()) {
      const std::string g = m.group, d = m.direction, name = m.name;
      if ((d == "min" || d == "one") && g != "pixels" && g != "motion" && name.back() != '_') o.push_back(name);
    }
    return o;
  }();
  return out;
}

[[noreturn]] void fail(const std::string& what) { throw ConfigError("tune: " + what); }

// One value of a range or choice list: JSON where it parses (numbers, true/false, quoted strings),
// else the bare text as a string.
json value_of(const std::string& text) {
  try {
    json v = json::parse(text);
    if (v.is_number() || v.is_boolean() || v.is_string()) return v;
  } catch (const json::exception&) {
  }
  return text;
}

bool is_integer_text(const std::string& s) { return std::regex_match(s, std::regex(R"(-?[0-9]{1,9})")); }

// "KEY=RANGE" -> {"key", "kind": float|int|choice, "lo", "hi", "log", "choices"}.
json parse_space(const std::string& text) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    fail("--space \"" + text + "\": expected KEY=RANGE (lo:hi, lo:hi:log or a,b,...)");
  const std::string key = text.substr(0, eq), range = text.substr(eq + 1);
  if (!std::regex_match(key, std::regex(R"([A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*)")))
    fail("--space " + text + ": \"" + key + "\" is not a key path (e.g. taa.alpha, ssaa_grid, material.glint_sigma)");
  json s = {{"key", key}};
  static const std::regex num_range(R"(([^:,]+):([^:,]+)(:log)?)");
  std::smatch m;
  if (std::regex_match(range, m, num_range)) {
    const json lo = value_of(m[1]), hi = value_of(m[2]);
    if (!lo.is_number() || !hi.is_number())
      fail("--space " + text + ": a range lo:hi needs two numbers (a list of choices is a,b,...)");
    const double a = lo.get<double>(), b = hi.get<double>();
    if (!(std::isfinite(a) && std::isfinite(b))) fail("--space " + text + ": the ends must be finite");
    if (!(a < b)) fail("--space " + text + ": lo must be below hi (got " + m[1].str() + " and " + m[2].str() + ")");
    const bool log = m[3].matched;
    if (log && !(a > 0)) fail("--space " + text + ": a log range needs lo > 0");
    const bool integer = is_integer_text(m[1]) && is_integer_text(m[2]);
    s["kind"] = integer ? "int" : "float";
    s["lo"] = lo;
    s["hi"] = hi;
    s["log"] = log;
  } else {
    json choices = json::array();
    size_t at = 0;
    while (at <= range.size()) {
      const size_t comma = std::min(range.find(',', at), range.size());
      const std::string item = range.substr(at, comma - at);
      if (item.empty()) fail("--space " + text + ": an empty choice");
      choices.push_back(value_of(item));
      at = comma + 1;
    }
    if (choices.size() < 2) fail("--space " + text + ": a list of choices needs at least two");
    s["kind"] = "choice";
    s["choices"] = choices;
  }
  return s;
}

// The variant with `value` at the dotted `key`.
json with_value(json variant, const std::string& key, const json& value) {
  json* at = &variant;
  size_t start = 0;
  for (size_t dot = key.find('.'); ; dot = key.find('.', start)) {
    const std::string part = key.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (dot == std::string::npos) {
      (*at)[part] = value;
      break;
    }
    json& next = (*at)[part];
    if (next.is_null()) next = json::object();
    if (!next.is_object()) fail("--space " + key + ": \"" + part + "\" of the base variant is not an object");
    at = &next;
    start = dot + 1;
  }
  return variant;
}

}  // namespace

std::vector<std::string> objective_names() { return objectives(); }

json tune_definition(const TuneOptions& o, const json& experiment, const std::string& file) {
  if (o.trials < 1) fail("--trials must be at least 1");
  if (o.workers < 1 || o.workers > 64) fail("--workers must be in 1 ... 64");
  if (o.sampler != "tpe" && o.sampler != "nsga2") fail("--sampler \"" + o.sampler + "\": allowed tpe, nsga2");
  if (o.storage != "sqlite" && o.storage != "journal")
    fail("--storage \"" + o.storage + "\": allowed sqlite (one machine), journal (a shared file system)");
  const ExperimentSpec spec = ExperimentSpec::from_json(experiment, file);  // the experiment as it is
  bool frame_sources = !spec.reference.frames.empty();
  for (const VariantSpec& v : spec.variants) frame_sources = frame_sources || !v.frames.empty();
  if (frame_sources)
    fail(file + " reads frames from files: a study renders its variant, so it needs an experiment that renders");
  const json& variants = experiment.at("variants");
  int base_index = -1;
  std::vector<std::string> names;
  for (size_t i = 0; i < variants.size(); ++i) {
    names.push_back(variants[i].value("name", ""));
    if (names.back() == o.base) base_index = int(i);
  }
  if (base_index < 0) fail("--base \"" + o.base + "\" is not a variant of " + file + "; its variants: " + join(names));
  if (o.space.empty()) fail("--space: at least one KEY=RANGE");
  if (o.objectives.empty()) fail("--objectives: at least one of " + join(objectives()));
  std::vector<std::string> seen;
  for (const std::string& m : o.objectives) {
    if (m.empty())
      fail("--objectives: an empty name (two commas in a row, or one at an end); allowed: " + join(objectives()));
    if (std::find(objectives().begin(), objectives().end(), m) == objectives().end())
      fail("--objectives: unknown objective \"" + m + "\"; allowed: " + join(objectives()));
    if (std::find(seen.begin(), seen.end(), m) != seen.end()) fail("--objectives: \"" + m + "\" twice");
    seen.push_back(m);
    // An objective the experiment does not measure (its "metrics" list leaves it out) would be missing
    // from every trial.
    const auto per_pixel = metrics::metric_names();
    bool measured = true;
    if (std::find(per_pixel.begin(), per_pixel.end(), m) != per_pixel.end())
      measured = std::find(spec.metrics.begin(), spec.metrics.end(), m) != spec.metrics.end();
    else if (m.rfind("glint_", 0) == 0)
      measured = spec.metric_options.glints;
    else if (m == "pooled_error")
      measured = spec.metric_options.pooled;
    if (!measured)
      fail("--objectives: \"" + m + "\" is not measured by " + file + " (its \"metrics\" list leaves it out)");
  }
  const json base = variants[size_t(base_index)];
  json space = json::array();
  std::vector<std::string> keys;
  for (const std::string& given : o.space) {
    // "material.glints.NAME" alone: the whole declared range of the base variant's glint model's parameter
    std::string text = given;
    const std::string own = "material.glints.";
    if (given.find('=') == std::string::npos && given.rfind(own, 0) == 0) {
      const std::string name = given.substr(own.size());
      const VariantSpec* bv = nullptr;
      for (const VariantSpec& v : spec.variants)
        if (v.name == o.base) bv = &v;
      const core::GlintModelDecl* decl = bv ? bv->material.glint_decl() : nullptr;
      const core::GlintParameter* gp = decl ? decl->parameter(name) : nullptr;
      if (!gp)
        fail("--space " + given + ": without a range, the key must be a parameter the base variant's glint model (" +
             (bv ? bv->material.glint_model : std::string("?")) + ") declares");
      auto real = [](double v) {  // always with a point or exponent: a float range, not an int one
        std::ostringstream r;
        r << std::setprecision(17) << v;
        std::string t = r.str();
        return t.find_first_of(".e") == std::string::npos ? t + ".0" : t;
      };
      text = given + "=" + (gp->is_bool ? std::string("false,true") : real(gp->lo) + ":" + real(gp->hi));
    }
    json s = parse_space(text);
    const std::string key = s["key"];
    if (key == "name") fail("--space name: the variant's name is not an option");
    if (std::find(keys.begin(), keys.end(), key) != keys.end()) fail("--space " + key + ": given twice");
    keys.push_back(key);
    // Each end (each choice) through the experiment schema: its message names the key and what it allows.
    std::vector<json> probes = s["kind"] == "choice" ? s["choices"].get<std::vector<json>>()
                                                      : std::vector<json>{s["lo"], s["hi"]};
    for (const json& value : probes) {
      json e = experiment;
      e["variants"][size_t(base_index)] = with_value(base, key, value);
      try {
        (void)ExperimentSpec::from_json(e, file);
      } catch (const ConfigError& err) {
        fail("--space " + text + ": with " + key + " = " + value.dump() + " the experiment is not valid: " + err.what());
      }
    }
    space.push_back(s);
  }
  return {{"schema", "glintlab-tune/1"},
          {"experiment", spec.name},
          {"base", o.base},
          {"base_variant", base},
          {"space", space},
          {"objectives", o.objectives},
          {"metric_info", metric_info_json(o.objectives)},
          {"sampler", o.sampler},
          {"seed", o.seed},
          {"storage", o.storage}};
}

namespace {

// An exclusive lock on DIR/.tune.lock for the life of the object.
class StudyLock {
 public:
  explicit StudyLock(const fs::path& dir) {
    fd_ = ::open((dir / ".tune.lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) throw ConfigError("tune: cannot open " + (dir / ".tune.lock").string() + ": " + std::strerror(errno));
    while (::flock(fd_, LOCK_EX) != 0 && errno == EINTR) {
    }
  }
  ~StudyLock() { ::close(fd_); }
  StudyLock(const StudyLock&) = delete;
  StudyLock& operator=(const StudyLock&) = delete;

 private:
  int fd_ = -1;
};

// What tells two studies apart (the budget, workers, cache and device may change between workers).
json identity(const json& d) {
  json i = d;
  for (const char* k : {"trials", "cache", "device", "glintlab", "experiment_file"}) i.erase(k);
  return i;
}

}  // namespace

int tune(const TuneOptions& o, std::ostream& log) {
  const std::string file = resolve_experiment_path(o.experiment);  // bad input: run_guarded, the caller's
  // its files by absolute paths: the trials run copies of it from their own folders
  const json experiment = with_absolute_paths(read_json_file(file), file);
  const std::string name = experiment.is_object() ? experiment.value("name", std::string()) : std::string();
  const fs::path dir = o.study_dir.empty() ? fs::path(results_path("tune")) / (name + "-" + o.base)
                                           : fs::path(o.study_dir);
  json def;
  try {
    def = tune_definition(o, experiment, file);
  } catch (const json::exception& e) {  // a value of the wrong type: the file's fault, named
    throw ConfigError("tune: " + file + ": " + e.what());
  }
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    log << "error: tune: cannot create the study folder " << dir.string() << ": " << ec.message() << "\n";
    return kExitIo;
  }
  char self[4096];
  const ssize_t n = ::readlink("/proc/self/exe", self, sizeof self - 1);
  def["glintlab"] = n > 0 ? std::string(self, size_t(n)) : std::string("glintlab");
  def["trials"] = o.trials;
  def["experiment_file"] = fs::absolute(file).string();
  def["cache"] = fs::absolute(o.cache_dir.empty() ? fs::path(results_path("cache/reference"))
                                                  : fs::path(o.cache_dir))
                     .string();
  def["device"] = o.device;
  try {
    StudyLock lock(dir);
    const fs::path study = dir / "study.json";
    // The study's trials live in its storage: a study that has begun (--resume, or trials/ written)
    // without it would start over and write over trials/0000...
    const fs::path storage = dir / (o.storage == "journal" ? "study.journal" : "study.db");
    const bool stored = fs::is_regular_file(storage) && fs::file_size(storage) > 0;
    if (!stored && (o.resume || fs::exists(dir / "trials"))) {
      log << "error: tune: " << (o.resume ? "--resume: " : "") << dir.string() << (fs::exists(dir / "trials") ? " holds trials/ but" : "")
          << " has " << (fs::exists(storage) ? "an empty " : "no ") << storage.string()
          << ", the study's storage: there is no study to continue (restore the file, or start a new study "
          << "in another --study folder without --resume)\n";
      return kExitBadInput;
    }
    if (fs::exists(study)) {
      const json old = read_json_file(study.string());
      if (identity(old) != identity(def)) {
        log << "error: tune: " << dir.string() << " holds another study (experiment \"" << old.value("experiment", "")
            << "\", base \"" << old.value("base", "") << "\"; its space, objectives, sampler, seed and storage are in "
            << study.string() << "); use another --study folder\n";
        return kExitBadInput;
      }
      if (!o.resume && old.value("trials", 0) != o.trials) {
        log << "error: tune: " << dir.string() << " is a study of " << old.value("trials", 0)
            << " trials; --trials " << o.trials << " changes its budget: add --resume to continue it so\n";
        return kExitBadInput;
      }
    } else {
      write_text_atomic(dir / "experiment.json", dump_json(experiment, 2) + "\n");
    }
    write_text_atomic(study, dump_json(def, 2) + "\n");
  } catch (const std::exception& e) {
    log << "error: tune: " << e.what() << "\n";
    return kExitIo;
  }
  log.flush();
  // The driver: Debian's Python (python3-optuna installs for it) unless GLINTLAB_PYTHON says otherwise.
  const char* py_env = std::getenv("GLINTLAB_PYTHON");
  const std::string py = py_env && *py_env ? py_env : (::access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3"
                                                                                                 : "python3");
  const std::string script = data_path("experiments/tune/glintlab_tune.py");
  std::vector<std::string> argv = {py, "-B", script, dir.string(), "--workers", std::to_string(o.workers)};
  std::vector<char*> args;
  for (auto& a : argv) args.push_back(a.data());
  args.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, args[0], nullptr, nullptr, args.data(), environ);
  if (rc != 0) {
    log << "error: tune: cannot run " << py << ": " << std::strerror(rc)
        << "; install the Debian package python3-optuna (./bootstrap.sh does)\n";
    return kExitIo;
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFSIGNALED(status)) {
    log << "error: tune: the driver was killed by signal " << WTERMSIG(status) << "\n";
    return kExitInternal;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : kExitInternal;
}

}  // namespace glintlab
