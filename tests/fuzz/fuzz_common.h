// Shared by the libFuzzer harnesses of tests/fuzz: a private temp directory, findings, and the
// GLINTLAB_FUZZ_IGNORE escape hatch.
//
// A *finding* is anything the harness's oracle rejects: an exception type the code under test must
// not throw, an invariant broken by an accepted input, a wrong exit code. It is printed as
//   FUZZ FINDING [<id>]: <message>
// on stderr and the process aborts, so libFuzzer stores the input as a crash artifact (and the
// sanitizers' own reports, leaks and timeouts end the run the same way).
//
// GLINTLAB_FUZZ_IGNORE="substring;substring;..." turns findings whose "<id>: <message>" contains
// one of the substrings into clean rejections (counted, reported once each on stderr). It exists to
// keep fuzzing past a known, reported defect until it is fixed; tests/fuzz/run.sh sets none.
#pragma once

#include <cxxabi.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <string>
#include <system_error>
#include <typeinfo>
#include <vector>

namespace glintlab_fuzz {

namespace fs = std::filesystem;

// mkdtemp under $TMPDIR (else /tmp); removed at normal exit (libFuzzer exits normally when its
// time or run budget is spent; after a crash the directory stays for inspection).
inline std::string make_temp_dir(const char* tag) {
  const char* base = std::getenv("TMPDIR");
  std::string tmpl = std::string(base && *base ? base : "/tmp") + "/glintlab-fuzz-" + tag + "-XXXXXX";
  std::vector<char> buf(tmpl.begin(), tmpl.end());
  buf.push_back('\0');
  if (!mkdtemp(buf.data())) {
    std::perror("glintlab fuzz: mkdtemp");
    std::abort();
  }
  static std::vector<std::string> dirs;
  if (dirs.empty())
    std::atexit([] {
      for (const auto& d : dirs) {
        std::error_code ec;
        fs::remove_all(d, ec);
      }
    });
  dirs.emplace_back(buf.data());
  return dirs.back();
}

inline void write_file(const std::string& path, const void* data, size_t size) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
  if (!f) {
    std::fprintf(stderr, "glintlab fuzz: cannot write %s\n", path.c_str());
    std::abort();
  }
}

inline void write_file(const std::string& path, const std::string& text) { write_file(path, text.data(), text.size()); }

// Demangled type name of the exception being handled (inside a catch block).
inline std::string current_exception_type() {
  std::type_info* t = abi::__cxa_current_exception_type();
  if (!t) return "<unknown>";
  int status = 0;
  std::unique_ptr<char, void (*)(void*)> d(abi::__cxa_demangle(t->name(), nullptr, nullptr, &status), std::free);
  return status == 0 && d ? std::string(d.get()) : std::string(t->name());
}

// "<type>: <what>" of the exception being handled (inside a catch block).
inline std::string current_exception_text() {
  std::string what;
  try {
    throw;
  } catch (const std::exception& e) {
    what = e.what();
  } catch (...) {
    what = "(not a std::exception)";
  }
  return current_exception_type() + ": " + what;
}

inline bool ignored(const std::string& text) {
  static const std::vector<std::string> patterns = [] {
    std::vector<std::string> p;
    const char* env = std::getenv("GLINTLAB_FUZZ_IGNORE");
    std::string s = env ? env : "";
    size_t start = 0;
    while (start <= s.size()) {
      size_t end = s.find(';', start);
      if (end == std::string::npos) end = s.size();
      if (end > start) p.push_back(s.substr(start, end - start));
      start = end + 1;
    }
    return p;
  }();
  for (const auto& p : patterns)
    if (text.find(p) != std::string::npos) {
      static std::set<std::string> seen;
      if (seen.insert(p).second) std::fprintf(stderr, "glintlab fuzz: ignoring (GLINTLAB_FUZZ_IGNORE): %s\n", text.c_str());
      return true;
    }
  return false;
}

// Reports a finding and aborts, unless GLINTLAB_FUZZ_IGNORE matches it (then it returns).
inline void finding(const std::string& id, const std::string& message) {
  const std::string text = id + ": " + message;
  if (ignored(text)) return;
  std::fprintf(stderr, "\nFUZZ FINDING [%s]: %s\n", id.c_str(), message.c_str());
  std::fflush(stderr);
  std::abort();
}

// libFuzzer's own byte-level mutator (for custom mutators to fall back on).
extern "C" size_t LLVMFuzzerMutate(uint8_t* data, size_t size, size_t max_size);

// The value of "-NAME=..." among libFuzzer's flags, or "".
inline std::string fuzzer_flag(int argc, char** argv, const std::string& name) {
  const std::string prefix = "-" + name + "=";
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]).rfind(prefix, 0) == 0) return std::string(argv[i]).substr(prefix.size());
  return "";
}

}  // namespace glintlab_fuzz
