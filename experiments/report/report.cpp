#include "experiments/report/report.h"

#include "core/util/data_dir.h"
#include "experiments/cli/commands.h"
#include "experiments/cli/exit_codes.h"

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <iostream>
#include <system_error>
#include <vector>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace fs = std::filesystem;

namespace glintlab {

namespace {

// The script's own exit codes besides those of exit_codes.h.
constexpr int kScriptMissingModule = 10;

constexpr const char* kPackages = "python3 python3-numpy python3-scipy python3-matplotlib python3-pil python3-jinja2";

struct Child {
  int spawn_error = 0;  // errno of a failed start (e.g. ENOENT), 0 if it ran
  int status = 0;       // waitpid status
  std::string output;   // stdout and stderr, interleaved
};

// Runs argv (argv[0] a path or a name looked up on PATH) with stdin from
// /dev/null and stdout + stderr captured.
Child run_child(const std::vector<std::string>& argv) {
  Child c;
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) {
    c.spawn_error = errno;
    return c;
  }
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&fa, fds[1], 1);
  posix_spawn_file_actions_adddup2(&fa, fds[1], 2);
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, args[0], &fa, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  ::close(fds[1]);
  if (rc != 0) {
    ::close(fds[0]);
    c.spawn_error = rc;
    return c;
  }
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n > 0) {
      c.output.append(buf, size_t(n));
    } else if (n < 0 && errno == EINTR) {
      continue;
    } else {
      break;
    }
  }
  ::close(fds[0]);
  while (::waitpid(pid, &c.status, 0) < 0 && errno == EINTR) {
  }
  return c;
}


}  // namespace

std::string report_script_path() { return data_path("experiments/report/glintlab_report.py"); }

int write_report(const std::string& run_dir, std::ostream& log) {
  std::error_code ec;
  if (!fs::is_directory(run_dir, ec)) {
    log << "error: report: " << run_dir << ": no such directory\n";
    return kExitBadInput;
  }
  if (!fs::is_regular_file(fs::path(run_dir) / "summary.json", ec)) {
    log << "error: report: " << (fs::path(run_dir) / "summary.json").string() << ": missing; " << run_dir
        << " is not a glintlab run directory (`glintlab run` writes one)\n";
    return kExitBadInput;
  }
  const char* script_env = std::getenv("GLINTLAB_REPORT_SCRIPT");
  const std::string script = script_env && *script_env ? std::string(script_env) : report_script_path();
  if (!fs::is_regular_file(script, ec)) {
    log << "error: report: the report script " << script << " is missing (set GLINTLAB_REPORT_SCRIPT to its path)\n";
    return kExitIo;
  }

  std::vector<std::string> pythons;
  if (const char* p = std::getenv("GLINTLAB_PYTHON"); p && *p) {
    pythons.push_back(p);
  } else {
    // Debian's interpreter first: python3-matplotlib and python3-pil install
    // for it, and a python3 earlier on PATH (a virtual environment, pyenv)
    // may lack them.
    if (::access("/usr/bin/python3", X_OK) == 0) pythons.push_back("/usr/bin/python3");
    pythons.push_back("python3");
  }

  std::string first_problem;  // what the first interpreter that could not do it said
  for (const std::string& py : pythons) {
    Child c = run_child({py, "-B", script, run_dir});
    if (c.spawn_error != 0) {
      if (first_problem.empty())
        first_problem = "error: report: cannot run " + py + ": " + std::strerror(c.spawn_error) +
                        "; install the Debian packages " + kPackages + " (./bootstrap.sh does)\n";
      continue;
    }
    if (WIFEXITED(c.status) && WEXITSTATUS(c.status) == kScriptMissingModule) {
      if (first_problem.empty()) first_problem = c.output;
      continue;
    }
    log << c.output;
    if (WIFSIGNALED(c.status)) {
      log << "error: report: " << py << " " << script << " was killed by signal " << WTERMSIG(c.status) << "\n";
      return kExitInternal;
    }
    const int code = WIFEXITED(c.status) ? WEXITSTATUS(c.status) : -1;
    switch (code) {
      case kExitOk:
      case kExitBadInput:
      case kExitIo:
        return code;
      default:
        log << "error: report: " << script << " failed (exit status " << code << ")\n";
        return kExitInternal;
    }
  }
  log << first_problem;
  if (!first_problem.empty() && first_problem.back() != '\n') log << "\n";
  return kExitIo;
}

void add_report_command(CLI::App& app, int& exit_code) {
  auto dir = std::make_shared<std::string>();
  CLI::App* c = app.add_subcommand(
      "report", "write DIR/report.html (error vs cost with Pareto fronts, per-frame curves, table of means, glint "
                "crops, animated sequences) and DIR/figures/ for an existing run directory");
  c->add_option("dir", *dir, "run directory written by `glintlab run`")->required();
  c->callback([dir, &exit_code] {
    exit_code = run_guarded([&] { return write_report(*dir, std::cerr); }, std::cerr);
  });
}

}  // namespace glintlab
