#include "vcd.h"

#include <map>

namespace wmra {
namespace sim {

namespace {
std::string code_of(size_t n) {
  std::string s;
  do {
    s.push_back((char)('!' + n % 94));
    n /= 94;
  } while (n);
  return s;
}
}  // namespace

VcdWriter::VcdWriter(const std::string& path, uint32_t cpu_hz) : f_(std::fopen(path.c_str(), "w")), cpu_hz_(cpu_hz) {}

VcdWriter::~VcdWriter() {
  if (!f_) return;
  begin();
  if (end_cycle_) at(end_cycle_);
  std::fclose(f_);
}

int VcdWriter::wire(const std::string& scope, const std::string& name) {
  signals_.push_back({scope, name, code_of(signals_.size()), false, 0, false});
  return (int)signals_.size() - 1;
}

int VcdWriter::real(const std::string& scope, const std::string& name) {
  signals_.push_back({scope, name, code_of(signals_.size()), true, 0, false});
  return (int)signals_.size() - 1;
}

void VcdWriter::begin() {
  if (started_ || !f_) return;
  started_ = true;
  std::fprintf(f_, "$timescale 1ns $end\n");
  std::map<std::string, std::vector<const Signal*>> scopes;
  for (const auto& s : signals_) scopes[s.scope].push_back(&s);
  for (const auto& [scope, list] : scopes) {
    std::fprintf(f_, "$scope module %s $end\n", scope.c_str());
    for (const Signal* s : list) {
      std::fprintf(f_, "$var %s %d %s %s $end\n", s->is_real ? "real" : "wire", s->is_real ? 64 : 1, s->code.c_str(),
                   s->name.c_str());
    }
    std::fprintf(f_, "$upscope $end\n");
  }
  std::fprintf(f_, "$enddefinitions $end\n");
}

void VcdWriter::at(uint64_t cycle) {
  begin();
  uint64_t ns = cycle * 1000000000ull / cpu_hz_;
  if (last_ns_ != UINT64_MAX && ns < last_ns_) ns = last_ns_;  // timer callbacks lag an edge by a few cycles
  if (ns != last_ns_) {
    std::fprintf(f_, "#%llu\n", (unsigned long long)ns);
    last_ns_ = ns;
  }
}

void VcdWriter::set(int id, uint64_t cycle, bool level) {
  Signal& s = signals_[id];
  if (!f_ || (s.known && (s.last != 0) == level)) return;
  s.known = true;
  s.last = level;
  at(cycle);
  std::fprintf(f_, "%d%s\n", level ? 1 : 0, s.code.c_str());
}

void VcdWriter::set(int id, uint64_t cycle, double value) {
  Signal& s = signals_[id];
  if (!f_ || (s.known && s.last == value)) return;
  s.known = true;
  s.last = value;
  at(cycle);
  std::fprintf(f_, "r%.9g %s\n", value, s.code.c_str());
}

}  // namespace sim
}  // namespace wmra
