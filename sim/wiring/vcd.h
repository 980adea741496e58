// A small VCD (value change dump) writer: 1-bit wires and real-valued signals, time in CPU
// cycles written in nanoseconds (16 MHz: 62.5 ns a cycle, rounded down).
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace wmra {
namespace sim {

class VcdWriter {
 public:
  explicit VcdWriter(const std::string& path, uint32_t cpu_hz = 16000000);
  ~VcdWriter();
  VcdWriter(const VcdWriter&) = delete;
  VcdWriter& operator=(const VcdWriter&) = delete;
  bool ok() const { return f_ != nullptr; }

  // declare every signal before the first change
  int wire(const std::string& scope, const std::string& name);
  int real(const std::string& scope, const std::string& name);
  void set(int id, uint64_t cycle, bool level);
  void set(int id, uint64_t cycle, double value);
  // the time the trace ends (written when the writer closes)
  void end_at(uint64_t cycle) { end_cycle_ = cycle; }

 private:
  void begin();
  void at(uint64_t cycle);
  struct Signal {
    std::string scope, name, code;
    bool is_real;
    double last;
    bool known;
  };
  FILE* f_ = nullptr;
  uint32_t cpu_hz_;
  std::vector<Signal> signals_;
  bool started_ = false;
  uint64_t last_ns_ = UINT64_MAX;
  uint64_t end_cycle_ = 0;
};

}  // namespace sim
}  // namespace wmra
