// scripts/flash against a fake avrdude: a missing or wrong PORT stops it at once with a message
// that names PORT and the serial ports there are, a hung avrdude is stopped at the bound, and
// the bootloader and ISP paths give avrdude the right arguments.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "test_files.h"

namespace {

const std::string kScript = FLASH_SCRIPT;
const std::string kOut = FLASH_TEST_OUT;

using wmra::test::exists;
using wmra::test::read_file;

// A directory of its own for each test (ctest runs them in parallel), with a hex file and a fake
// avrdude that writes its arguments, one a line, to avrdude.args, then does what FAKE_AVRDUDE
// says: "hang" (for 60 s, far beyond the bound the test sets; exec, so that timeout's signal
// reaches the sleep itself), "fail", or succeeds.
struct Workdir {
  std::string dir, hex, avrdude, args;
  Workdir() {
    dir = kOut + "/flash_" + ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::system(("rm -rf '" + dir + "' && mkdir -p '" + dir + "'").c_str());
    hex = dir + "/image.hex";
    std::ofstream(hex) << ":00000001FF\n";
    avrdude = dir + "/avrdude";
    args = dir + "/avrdude.args";
    std::ofstream(avrdude) << "#!/bin/sh\n"
                              "printf '%s\\n' \"$@\" > '" + args + "'\n"
                              "case \"${FAKE_AVRDUDE:-}\" in\n"
                              "  hang) exec sleep 60 ;;\n"
                              "  fail) echo 'avrdude: ser_open(): cannot open port' >&2; exit 1 ;;\n"
                              "esac\n";
    chmod(avrdude.c_str(), 0755);
  }
  // the lines avrdude got, or none when it did not run
  std::vector<std::string> avrdude_args() const {
    std::vector<std::string> lines;
    std::istringstream in(read_file(args));
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    return lines;
  }
};

struct FlashRun {
  int status;
  std::string out, err;
  double seconds;
};

// scripts/flash with only the given settings of PORT, PROGRAMMER, FLASH_TIMEOUT_S (not ctest's)
// and the fake avrdude
FlashRun flash(const Workdir& w, const std::string& settings, const std::string& args) {
  const std::string command = "env -u PORT -u PROGRAMMER -u FLASH_TIMEOUT_S -u FAKE_AVRDUDE AVRDUDE='" + w.avrdude +
                              "' " + settings + " '" + kScript + "' " + args + " > '" + w.dir + "/out' 2> '" + w.dir +
                              "/err'";
  const auto start = std::chrono::steady_clock::now();
  const int s = std::system(command.c_str());
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return {WIFEXITED(s) ? WEXITSTATUS(s) : -1, read_file(w.dir + "/out"), read_file(w.dir + "/err"), seconds};
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// a wrong port: exit 2 within 5 s, a message naming PORT, the ports there are and the CH340
// hint, and avrdude never started
void expect_port_refused(const FlashRun& r, const Workdir& w, const std::string& port_words) {
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_LT(r.seconds, 5.0);
  EXPECT_EQ(r.out, "");
  EXPECT_TRUE(has(r.err, port_words)) << r.err;
  EXPECT_TRUE(has(r.err, "serial ports here: ")) << r.err;
  EXPECT_TRUE(has(r.err, "CH340 clones appear as /dev/ttyUSB0")) << r.err;
  EXPECT_TRUE(w.avrdude_args().empty()) << "avrdude ran";
}

}  // namespace

TEST(FlashScript, WithoutPortItStopsAtOnceAndSaysToSetIt) {
  Workdir w;
  expect_port_refused(flash(w, "", "'" + w.hex + "'"), w, "set PORT to the Mega's serial port, e.g. PORT=/dev/ttyACM0");
}

TEST(FlashScript, APortThatDoesNotExistIsRefusedAtOnce) {
  Workdir w;
  expect_port_refused(flash(w, "PORT=/nonexistent", "'" + w.hex + "'"), w,
                      "PORT=/nonexistent is not a serial port: it does not exist");
}

TEST(FlashScript, ACharacterDeviceThatIsNotATtyIsRefusedAtOnce) {
  Workdir w;
  expect_port_refused(flash(w, "PORT=/dev/null", "'" + w.hex + "'"), w,
                      "PORT=/dev/null is not a serial port: /dev/null is not a tty");
}

TEST(FlashScript, TheBootloaderPathWritesWithoutChipErase) {
  // any tty the script accepts will do: avrdude is the fake, nothing opens the port
  if (!exists("/sys/class/tty/tty")) GTEST_SKIP() << "no /sys/class/tty/tty to stand for a serial port";
  Workdir w;
  const FlashRun r = flash(w, "PORT=/dev/tty", "'" + w.hex + "'");
  EXPECT_EQ(r.status, 0) << r.err;
  const std::vector<std::string> expected = {"-c", "wiring", "-p", "atmega2560", "-b", "115200", "-D",
                                             "-P", "/dev/tty", "-U", "flash:w:" + w.hex + ":i"};
  EXPECT_EQ(w.avrdude_args(), expected);
}

TEST(FlashScript, AnIspProgrammerErasesTheChipAndNeedsNoPort) {
  Workdir w;
  const FlashRun r = flash(w, "PROGRAMMER=usbasp", "'" + w.hex + "'");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(has(r.out, "through the ISP programmer usbasp")) << r.out;
  const std::vector<std::string> expected = {"-c", "usbasp", "-p", "atmega2560", "-U", "flash:w:" + w.hex + ":i"};
  EXPECT_EQ(w.avrdude_args(), expected);  // no -D (the chip is erased), no -P
}

TEST(FlashScript, AnIspProgrammerGetsThePortWhenOneIsGiven) {
  Workdir w;
  const FlashRun r = flash(w, "PROGRAMMER=stk500v2 PORT=/dev/ttyUSB7", "'" + w.hex + "'");
  EXPECT_EQ(r.status, 0) << r.err;
  const std::vector<std::string> expected = {"-c", "stk500v2", "-p", "atmega2560", "-P", "/dev/ttyUSB7",
                                             "-U", "flash:w:" + w.hex + ":i"};
  EXPECT_EQ(w.avrdude_args(), expected);
}

TEST(FlashScript, AHungAvrdudeIsStoppedAtTheBound) {
  Workdir w;
  const FlashRun r = flash(w, "PROGRAMMER=usbasp FAKE_AVRDUDE=hang FLASH_TIMEOUT_S=2", "'" + w.hex + "'");
  EXPECT_EQ(r.status, 1);
  EXPECT_GE(r.seconds, 1.9);
  EXPECT_LT(r.seconds, 6.0);  // the bound, not the fake's 60 s
  EXPECT_TRUE(has(r.err, "avrdude did not finish within 2 s and was stopped")) << r.err;
  EXPECT_FALSE(w.avrdude_args().empty());
}

TEST(FlashScript, AFailingAvrdudeFailsTheFlash) {
  Workdir w;
  const FlashRun r = flash(w, "PROGRAMMER=usbasp FAKE_AVRDUDE=fail", "'" + w.hex + "'");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(has(r.err, "avrdude: ser_open(): cannot open port")) << r.err;
  EXPECT_TRUE(has(r.err, "flash: avrdude failed (exit status 1)")) << r.err;
  EXPECT_FALSE(has(r.out, "done")) << r.out;
}

TEST(FlashScript, BadUsageExitsTwoWithoutRunningAvrdude) {
  Workdir w;
  for (const std::string& args : {std::string(""), "'" + w.dir + "/no-such.hex'", std::string("--frobnicate")}) {
    const FlashRun r = flash(w, "PROGRAMMER=usbasp", args);
    EXPECT_EQ(r.status, 2) << args;
    EXPECT_EQ(r.out, "") << args;
    EXPECT_TRUE(has(r.err, "flash: ")) << args << ": " << r.err;
  }
  const FlashRun r = flash(w, "PROGRAMMER=usbasp FLASH_TIMEOUT_S=soon", "'" + w.hex + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(has(r.err, "FLASH_TIMEOUT_S='soon' is not a whole number of seconds")) << r.err;
  EXPECT_TRUE(w.avrdude_args().empty()) << "avrdude ran";
}
