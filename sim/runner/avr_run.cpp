// avr-run: run an ATmega2560 image in simavr at 16 MHz, print its console, time its regions.
//
//   avr-run IMAGE.elf [--max-cycles N] [--timings FILE.json] [--profile FILE]
//
// --profile writes the cycles spent at each instruction address ("0xADDR cycles" lines,
// byte addresses as avr-objdump and avr-addr2line use them).
// The image names its regions by printing lines "@ID NAME" on the console. Each region's
// cycle count is the core's cycle counter between the start and stop writes, less the cost
// of an empty region (the image's region id 1 must be that empty calibration region).
// Exit status: 0 when the image stopped by itself (sleep with interrupts off), 1 otherwise.
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>

#include <fcntl.h>
#include <unistd.h>

#include "probe_ports.h"
#include "sim_avr.h"
#include "sim_elf.h"
#include "sim_io.h"

namespace {

struct RegionStats {
  uint64_t count = 0;
  uint64_t sum = 0;
  uint64_t max = 0;
  uint64_t min = UINT64_MAX;
};

struct Probe {
  avr_t* avr = nullptr;
  uint64_t start_cycle[256] = {};
  bool open[256] = {};
  RegionStats stats[256];
  std::string line;
  std::map<int, std::string> names;
};

Probe probe;

void on_console(avr_t*, avr_io_addr_t, uint8_t v, void*) {
  std::fputc(v, stdout);
  if (v == '\n') {
    if (probe.line.size() > 1 && probe.line[0] == '@') {
      char name[128];
      int id = 0;
      if (std::sscanf(probe.line.c_str() + 1, "%d %127s", &id, name) == 2 && id > 0 && id < 256) {
        probe.names[id] = name;
      }
    }
    probe.line.clear();
  } else {
    probe.line.push_back((char)v);
  }
}

void on_start(avr_t* avr, avr_io_addr_t, uint8_t id, void*) {
  probe.start_cycle[id] = avr->cycle;
  probe.open[id] = true;
}

void on_stop(avr_t* avr, avr_io_addr_t, uint8_t id, void*) {
  if (!probe.open[id]) return;
  probe.open[id] = false;
  const uint64_t c = avr->cycle - probe.start_cycle[id];
  RegionStats& s = probe.stats[id];
  s.count++;
  s.sum += c;
  if (c > s.max) s.max = c;
  if (c < s.min) s.min = c;
}

int usage() {
  std::fprintf(stderr, "usage: avr-run IMAGE.elf [--max-cycles N] [--timings FILE.json] [--profile FILE]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage();
  const char* image = argv[1];
  uint64_t max_cycles = 4000000000ull;
  const char* timings_path = nullptr;
  const char* profile_path = nullptr;
  for (int i = 2; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--max-cycles") && i + 1 < argc) {
      max_cycles = std::strtoull(argv[++i], nullptr, 10);
    } else if (!std::strcmp(argv[i], "--timings") && i + 1 < argc) {
      timings_path = argv[++i];
    } else if (!std::strcmp(argv[i], "--profile") && i + 1 < argc) {
      profile_path = argv[++i];
    } else {
      return usage();
    }
  }

  elf_firmware_t firmware;
  std::memset(&firmware, 0, sizeof firmware);
  // libsimavr reports what it loaded on stdout, which carries the image's console: mute it
  std::fflush(stdout);
  const int saved_stdout = dup(STDOUT_FILENO);
  const int null_fd = open("/dev/null", O_WRONLY);
  dup2(null_fd, STDOUT_FILENO);
  const int read_status = elf_read_firmware(image, &firmware);
  std::fflush(stdout);
  dup2(saved_stdout, STDOUT_FILENO);
  close(null_fd);
  close(saved_stdout);
  if (read_status != 0) {
    std::fprintf(stderr, "avr-run: cannot read %s\n", image);
    return 2;
  }
  std::strcpy(firmware.mmcu, "atmega2560");
  firmware.frequency = 16000000;
  avr_t* avr = avr_make_mcu_by_name(firmware.mmcu);
  if (!avr) {
    std::fprintf(stderr, "avr-run: simavr has no atmega2560 core\n");
    return 2;
  }
  avr_init(avr);
  avr_load_firmware(avr, &firmware);
  probe.avr = avr;
  avr_register_io_write(avr, WMRA_PROBE_CONSOLE_IO + WMRA_PROBE_DATA_OFFSET, on_console, nullptr);
  avr_register_io_write(avr, WMRA_PROBE_START_IO + WMRA_PROBE_DATA_OFFSET, on_start, nullptr);
  avr_register_io_write(avr, WMRA_PROBE_STOP_IO + WMRA_PROBE_DATA_OFFSET, on_stop, nullptr);

  int state = cpu_Running;
  std::map<uint32_t, uint64_t> profile;
  while (state != cpu_Done && state != cpu_Crashed && avr->cycle < max_cycles) {
    if (profile_path) {
      const uint32_t pc = avr->pc;
      const uint64_t before = avr->cycle;
      state = avr_run(avr);
      profile[pc] += avr->cycle - before;
    } else {
      state = avr_run(avr);
    }
  }
  std::fflush(stdout);
  if (profile_path) {
    FILE* f = std::fopen(profile_path, "w");
    if (!f) {
      std::fprintf(stderr, "avr-run: cannot write %s\n", profile_path);
      return 2;
    }
    for (const auto& [pc, cycles] : profile) std::fprintf(f, "0x%x %" PRIu64 "\n", pc, cycles);
    std::fclose(f);
  }

  const uint64_t empty = probe.stats[1].count ? probe.stats[1].min : 0;
  if (timings_path) {
    FILE* f = std::fopen(timings_path, "w");
    if (!f) {
      std::fprintf(stderr, "avr-run: cannot write %s\n", timings_path);
      return 2;
    }
    std::fprintf(f, "{\n  \"image\": \"%s\",\n  \"f_cpu_hz\": 16000000,\n  \"empty_region_cycles\": %" PRIu64, image, empty);
    for (const auto& [id, name] : probe.names) {
      const RegionStats& s = probe.stats[id];
      if (id == 1 || s.count == 0) continue;
      std::fprintf(f, ",\n  \"%s\": {\"cycles\": %.1f, \"max\": %" PRIu64 ", \"min\": %" PRIu64 ", \"n\": %" PRIu64 "}",
                   name.c_str(), (double)s.sum / s.count - empty, s.max - empty, s.min - empty, s.count);
    }
    std::fprintf(f, "\n}\n");
    std::fclose(f);
  }
  if (state != cpu_Done) {
    std::fprintf(stderr, "avr-run: image did not finish (state %d after %" PRIu64 " cycles)\n", state, (uint64_t)avr->cycle);
    return 1;
  }
  return 0;
}
