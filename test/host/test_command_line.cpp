// The command-line convention of the tools and scripts: --help and -h print to stdout with exit
// status 0, an unknown option goes to stderr with exit status 2, and a tool's --version prints one
// line, its name and the product's version (firmware/config/version.h). The scripts (every
// executable in scripts/) answer --help and a bad option without installing or building anything:
// cmake, apt-get and sudo are shims that leave a mark, and the build directory stays absent.
#include <gtest/gtest.h>

#include <dirent.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "test_files.h"

#include "config/version.h"

namespace {

const std::string kOut = COMMAND_LINE_TEST_OUT;
const std::string kScripts = SCRIPTS_DIR;

using wmra::test::exists;
using wmra::test::read_file;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

struct CommandRun {
  int status;
  std::string out, err;
};

// A directory of its own for each test (ctest runs them in parallel): shims for the commands
// that install or build, and a build directory that nothing should create.
struct Workdir {
  std::string dir, shims, marks, build;
  Workdir() {
    std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::replace(name.begin(), name.end(), '/', '_');
    dir = kOut + "/command_line_" + name;
    shims = dir + "/bin";
    marks = dir + "/called";
    build = dir + "/build";
    std::system(("rm -rf '" + dir + "' && mkdir -p '" + shims + "'").c_str());
    for (const char* tool : {"cmake", "ctest", "make", "apt-get", "sudo"}) {
      const std::string shim = shims + "/" + tool;
      std::ofstream(shim) << "#!/bin/sh\necho \"" << tool << " $*\" >> '" << marks << "'\nexit 97\n";
      chmod(shim.c_str(), 0755);
    }
  }
  // at most 30 s: a script that starts to build is stopped soon (its shims fail it at once)
  CommandRun run(const std::string& program, const std::string& args) const {
    const std::string command = "PATH='" + shims + "':\"$PATH\" WMRA_BUILD_DIR='" + build + "' timeout 30 '" + program +
                                "' " + args + " > '" + dir + "/out' 2> '" + dir + "/err' < /dev/null";
    const int s = std::system(command.c_str());
    return {WIFEXITED(s) ? WEXITSTATUS(s) : -1, read_file(dir + "/out"), read_file(dir + "/err")};
  }
  // what the script tried to install or build ("" when nothing)
  std::string called() const { return read_file(marks); }
};

// ------------------------------------------------------------------------------ the tools

struct Tool {
  const char* name;
  const char* path;
};
const Tool kTools[] = {{"armkin", ARMKIN_BIN}, {"jointsim", JOINTSIM_BIN}};
void PrintTo(const Tool& t, std::ostream* os) { *os << t.name; }

class ToolCommandLine : public ::testing::TestWithParam<Tool> {};

TEST_P(ToolCommandLine, HelpGoesToStdoutWithStatusZero) {
  const Tool t = GetParam();
  Workdir w;
  for (const char* option : {"--help", "-h"}) {
    const CommandRun r = w.run(t.path, option);
    EXPECT_EQ(r.status, 0) << option;
    EXPECT_EQ(r.out.rfind(std::string("usage: ") + t.name + " ", 0), 0u) << option << ": " << r.out;
    EXPECT_EQ(r.err, "") << option;
  }
}

TEST_P(ToolCommandLine, AnUnknownOptionGoesToStderrWithStatusTwo) {
  const Tool t = GetParam();
  Workdir w;
  const CommandRun r = w.run(t.path, "--no-such-option");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err.rfind(std::string(t.name) + ": unknown option '--no-such-option'", 0), 0u) << r.err;
}

TEST_P(ToolCommandLine, VersionIsOneLineWithTheNameAndTheProductVersion) {
  const Tool t = GetParam();
  Workdir w;
  const CommandRun r = w.run(t.path, "--version");
  const wmra::config::Version v = wmra::config::kProductVersion;
  const std::string expected = std::string(t.name) + " " + std::to_string(v.major) + "." + std::to_string(v.minor) +
                               "." + std::to_string(v.patch) + " ";
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out.rfind(expected, 0), 0u) << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
  EXPECT_EQ(r.out.back(), '\n');
  EXPECT_EQ(r.err, "");
}

INSTANTIATE_TEST_SUITE_P(Tools, ToolCommandLine, ::testing::ValuesIn(kTools),
                         [](const ::testing::TestParamInfo<Tool>& i) { return std::string(i.param.name); });

// ------------------------------------------------------------------------------ the scripts

// every executable file in scripts/ (common.sh and chromium.sh are sourced, not run)
std::vector<std::string> scripts() {
  std::vector<std::string> names;
  if (DIR* d = opendir(kScripts.c_str())) {
    while (const dirent* e = readdir(d)) {
      const std::string name = e->d_name;
      const std::string path = kScripts + "/" + name;
      struct stat st;
      if (name[0] != '.' && stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && (st.st_mode & S_IXUSR)) {
        names.push_back(name);
      }
    }
    closedir(d);
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::string test_name(std::string name) {
  for (char& c : name) {
    if (!isalnum((unsigned char)c)) c = '_';
  }
  return name;
}

class ScriptCommandLine : public ::testing::TestWithParam<std::string> {};

TEST(ScriptsDirectory, HoldsTheScripts) {
  const std::vector<std::string> s = scripts();
  for (const char* expected : {"demo", "flash", "test"}) {
    EXPECT_NE(std::find(s.begin(), s.end(), expected), s.end()) << expected << " not found in " << kScripts;
  }
}

TEST_P(ScriptCommandLine, HelpGoesToStdoutWithStatusZeroAndNothingIsBuilt) {
  const std::string name = GetParam();
  const std::string stem = name.substr(0, name.find('.'));
  Workdir w;
  for (const char* option : {"--help", "-h"}) {
    const CommandRun r = w.run(kScripts + "/" + name, option);
    EXPECT_EQ(r.status, 0) << option << ": " << r.err;
    EXPECT_TRUE(has(r.out, "usage: ")) << option << ": " << r.out;
    EXPECT_TRUE(has(r.out, stem)) << option << ": " << r.out;
    EXPECT_EQ(r.err, "") << option;
  }
  EXPECT_EQ(w.called(), "");
  EXPECT_FALSE(exists(w.build)) << "a build directory appeared";
}

TEST_P(ScriptCommandLine, AnUnknownOptionGoesToStderrWithStatusTwoAndNothingIsBuilt) {
  const std::string name = GetParam();
  const std::string stem = name.substr(0, name.find('.'));
  Workdir w;
  const CommandRun r = w.run(kScripts + "/" + name, "--no-such-option");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_TRUE(has(r.err, stem + ": ") || has(r.err, stem + ".py: ")) << r.err;
  EXPECT_TRUE(has(r.err, "--no-such-option")) << r.err;
  EXPECT_EQ(w.called(), "");
  EXPECT_FALSE(exists(w.build)) << "a build directory appeared";
}

INSTANTIATE_TEST_SUITE_P(Scripts, ScriptCommandLine, ::testing::ValuesIn(scripts()),
                         [](const ::testing::TestParamInfo<std::string>& i) { return test_name(i.param); });

}  // namespace
