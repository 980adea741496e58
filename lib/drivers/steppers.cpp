#include "drivers/steppers.h"

#include <avr/interrupt.h>
#include <avr/io.h>
#include <util/atomic.h>

#include "drivers/isr_scratch.h"
#include "drivers/pins.h"
#include "wmra_mega/board.h"

namespace wmra {
namespace steppers {

namespace {

constexpr const board::StepperPins& kPins(uint8_t i) {
  return i == 0 ? board::kStepperJ1 : i == 1 ? board::kStepperJ5 : board::kStepperJ6;
}
constexpr uint8_t com_shift(uint8_t i) { return (uint8_t)m2560::com_shift(kPins(i).step.channel); }
constexpr uint8_t ocie_bit(uint8_t i) { return (uint8_t)(OCIE5A + (uint8_t)kPins(i).step.channel); }
constexpr uint8_t foc_bit(uint8_t i) { return (uint8_t)(FOC5A - (uint8_t)kPins(i).step.channel); }
constexpr uint8_t kComToggle = 1, kComClear = 2;
static_assert(m2560::pin_register(board::kStepperJ1.dir.port) < 0x40 && m2560::pin_register(board::kStepperJ5.dir.port) < 0x40 &&
                  m2560::pin_register(board::kStepperJ6.dir.port) < 0x40,
              "DIR and EN pins on low ports (sbi/cbi: atomic)");
// An edge is never scheduled less than this far ahead of the counter (8 us): the ISR's writes
// after computing it take far less, so the compare cannot be passed unseen.
constexpr uint16_t kMinLeadTicks = 2;
constexpr uint16_t kRetimeMarginTicks = 4;
constexpr uint16_t kTicksPerService = kTickHz / kServiceHz;

// What a channel's ISR reads and writes; the main loop touches it with interrupts off.
struct Channel {
  uint16_t left;          // steps still to make: the channel stops at the edge that makes it 0
  uint16_t interval;      // whole ticks between edges
  uint8_t interval_frac;  // and 1/256 ticks
  uint8_t frac;           // the next edge's fraction
};
volatile uint8_t g_running;  // bit i: channel i has an edge scheduled
volatile bool g_killed = true;
volatile bool g_halting;  // halt_trains() until resume()
// One channel's state in one place: service()'s loop walks one table (a table per field kept
// six pointers, which avr-gcc spilled to the stack).
struct ChannelState {
  Channel isr;
  // main loop only: left as last read or written, and steps made before that not yet counted
  uint16_t base;
  uint16_t uncounted;
  uint32_t handed_q8;  // the interval last handed over
  int8_t dir;
  Rate rate;
};
ChannelState g_ch[kCount];

inline void set_com(uint8_t i, uint8_t com) {
  TCCR5A = (uint8_t)((TCCR5A & ~(3 << com_shift(i))) | (com << com_shift(i)));
}

inline void set_dir(uint8_t i, int8_t dir) {
  if (dir > 0) {
    pins::reg8(m2560::port_register(kPins(i).dir.port)) |= (uint8_t)(1 << kPins(i).dir.bit);
  } else {
    pins::reg8(m2560::port_register(kPins(i).dir.port)) &= (uint8_t)~(1 << kPins(i).dir.bit);
  }
}

// The compare unit toggled STEP high at the edge; a forced compare toggles it low again, 44
// cycles after the match at the earliest (the DRV8825 needs 1.9 us, 30 cycles). Then the next
// edge, one interval (Q8: the fraction's carry) after this one, or kMinLeadTicks from now if
// that is already close or past (late is the sign of edge - lead - now: intervals are below
// 32,768 ticks, kStepMaxInterval_ticks <= 25,000 in firmware/config/joints_config.h). At the
// step that brings `left` to 0 the channel stops (its compare output and interrupt off).
// Assembly, three registers and SREG saved, two of them in the scratch registers
// (isr_scratch.h): 73 cycles. In C (-O2) the ISR saved ten and took 114, in assembly with a
// fourth register for the counter's copy and every save a push 82; three channels at 20 kHz
// run it 60,000 times a second. The counter is compared byte by byte against edge - lead (its
// high byte read from the timer's TEMP after the low one: one read of the counter), and lead
// added back; a late edge reads the counter again (now, or a count later: still kMinLeadTicks
// ahead of it, as before the edge at the first read's count + lead).
template <uint8_t I>
__attribute__((always_inline)) inline void on_edge() {
  asm volatile(
      "out  %[scratch_a], r24\n\t"
      "in   r24, __SREG__\n\t"
      "out  %[scratch_b], r24\n\t"
      "push r25\n\t"
      "push r26\n\t"
      "lds  r24, %[left]\n\t"
      "lds  r25, %[left]+1\n\t"
      "sbiw r24, 1\n\t"
      "sts  %[left]+1, r25\n\t"
      "sts  %[left], r24\n\t"
      "breq 2f\n\t"
      "lds  r24, %[frac]\n\t"
      "lds  r25, %[ifrac]\n\t"
      "add  r24, r25\n\t"  // carry: the fractions' overflow, added below
      "sts  %[frac], r24\n\t"
      "lds  r24, %[ocr]\n\t"
      "lds  r26, %[ival]\n\t"
      "adc  r24, r26\n\t"
      "lds  r25, %[ocr]+1\n\t"
      "lds  r26, %[ival]+1\n\t"
      "adc  r25, r26\n\t"
      "ldi  r26, %[foc]\n\t"
      "sts  %[tccrc], r26\n\t"  // the pulse ends
      "sbiw r24, %[lead]\n\t"
      "lds  r26, %[tcnt]\n\t"
      "cp   r24, r26\n\t"
      "lds  r26, %[tcnt]+1\n\t"
      "cpc  r25, r26\n\t"
      "brmi 4f\n\t"
      "adiw r24, %[lead]\n"
      "1:\n\t"
      "sts  %[ocr]+1, r25\n\t"
      "sts  %[ocr], r24\n"
      "3:\n\t"
      "pop  r26\n\t"
      "pop  r25\n\t"
      "in   r24, %[scratch_b]\n\t"
      "out  __SREG__, r24\n\t"
      "in   r24, %[scratch_a]\n\t"
      "reti\n"
      "4:\n\t"
      "lds  r24, %[tcnt]\n\t"
      "lds  r25, %[tcnt]+1\n\t"
      "adiw r24, %[lead]\n\t"
      "rjmp 1b\n"
      "2:\n\t"
      "lds  r24, %[timsk]\n\t"
      "andi r24, %[ocie_keep]\n\t"
      "sts  %[timsk], r24\n\t"
      "lds  r24, %[running]\n\t"
      "andi r24, %[run_keep]\n\t"
      "sts  %[running], r24\n\t"
      "ldi  r24, %[foc]\n\t"  // the pulse ends (after the two writes above: 1.9 us)
      "sts  %[tccrc], r24\n\t"
      "lds  r24, %[tccra]\n\t"
      "andi r24, %[com_keep]\n\t"
      "sts  %[tccra], r24\n\t"
      "rjmp 3b\n\t"
      :
      : [left] "i"(&g_ch[I].isr.left), [frac] "i"(&g_ch[I].isr.frac), [ifrac] "i"(&g_ch[I].isr.interval_frac),
        [ival] "i"(&g_ch[I].isr.interval), [ocr] "n"(m2560::timer_registers(kPins(I).step.timer).ocr[(int)kPins(I).step.channel]),
        [foc] "n"(1 << foc_bit(I)), [tccrc] "n"(_SFR_MEM_ADDR(TCCR5C)), [tcnt] "n"(_SFR_MEM_ADDR(TCNT5L)),
        [lead] "n"(kMinLeadTicks), [tccra] "n"(_SFR_MEM_ADDR(TCCR5A)), [com_keep] "n"((uint8_t) ~(3 << com_shift(I))),
        [timsk] "n"(_SFR_MEM_ADDR(TIMSK5)), [ocie_keep] "n"((uint8_t) ~(1 << ocie_bit(I))), [running] "i"(&g_running),
        [run_keep] "n"((uint8_t) ~(1 << I)), [scratch_a] "n"(isr_scratch::kA_io), [scratch_b] "n"(isr_scratch::kB_io));
}

// With interrupts off: the channel's first edge one interval from now, DIR set first (the
// DRV8825's 650 ns setup time is far shorter than kMinLeadTicks).
void start_channel(uint8_t i, int8_t dir, uint32_t interval_q8, uint16_t left) {
  set_dir(i, dir);
  g_ch[i].dir = dir;
  Channel& c = g_ch[i].isr;
  c.left = left;
  c.interval = (uint16_t)(interval_q8 >> 8);
  c.interval_frac = (uint8_t)interval_q8;
  c.frac = 0;
  pins::ocr16(kPins(i).step) = (uint16_t)(TCNT5 + c.interval);
  TIFR5 = (uint8_t)(1 << ocie_bit(i));  // a stale match flag must not fire at once
  set_com(i, kComToggle);
  TIMSK5 |= (uint8_t)(1 << ocie_bit(i));
  g_running |= (uint8_t)(1 << i);
}

// The steps a channel made since its count was `now` (its ISR's steps left), into its ramp.
inline void count_from(ChannelState& ch, uint16_t now) {
  const uint16_t made = (uint16_t)(ch.uncounted + (uint16_t)(ch.base - now));
  ch.uncounted = 0;
  ch.base = now;
  if (made != 0) ch.rate.count_steps(ch.dir > 0 ? (int32_t)made : -(int32_t)made);
}

// The steps a channel (bit: its bit in g_running) made since the last count, into its ramp;
// returns the direction of the edge it still has scheduled (0: stopped).
int8_t count_made(ChannelState& ch, uint8_t bit) {
  uint16_t now;
  bool running;
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
    now = ch.isr.left;
    running = g_running & bit;
  }
  count_from(ch, now);
  return running ? ch.dir : 0;
}

// With interrupts off, a running channel's interval from its next edge on. An edge more than a
// service period away is moved to one new interval after the last edge (or to at once), so that
// a speed change never waits behind a long interval (the first ones from rest). Only if it is
// kRetimeMarginTicks or more ahead: it cannot then match between the counter's read and the
// write (it would be a step made twice).
inline void set_interval(uint8_t i, Channel& c, uint32_t interval_q8) {
  const uint16_t interval = (uint16_t)(interval_q8 >> 8);
  if (interval != c.interval && c.interval > kTicksPerService) {
    const uint16_t tcnt = TCNT5;
    const uint16_t old_edge = pins::ocr16(kPins(i).step);
    if ((int16_t)(old_edge - tcnt) >= (int16_t)kRetimeMarginTicks) {
      uint16_t edge = (uint16_t)(old_edge - c.interval + interval);
      if ((int16_t)(edge - tcnt) < (int16_t)kMinLeadTicks) edge = (uint16_t)(tcnt + kMinLeadTicks);
      pins::ocr16(kPins(i).step) = edge;
    }
  }
  c.interval = interval;
  c.interval_frac = (uint8_t)interval_q8;
}

// Hands the ISR its plan. Steps made since count_made() are counted at the next one (a
// position move's steps left shrink by them).
void hand_over(uint8_t i, uint8_t bit, const control::StepPlan& p, int32_t speed_q8) {
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
    if (g_killed) return;
    ChannelState& ch = g_ch[i];
    Channel& c = ch.isr;
    const uint16_t now = c.left;
    const uint16_t since = (uint16_t)(ch.base - now);
    ch.uncounted = (uint16_t)(ch.uncounted + since);
    uint16_t left = p.steps_left;
    // the target reached meanwhile (the ISR stopped on it): not started again
    const bool arrived = left != Rate::kNoStop && since >= left;
    if (left != Rate::kNoStop && !arrived) left = (uint16_t)(left - since);
    if (p.interval_q8 == 0 || arrived) left = 1;  // the scheduled edge, if any, is the last
    if (g_running & bit) {
      c.left = left;
      if (p.interval_q8 != 0) set_interval(i, c, p.interval_q8);
    } else if (p.interval_q8 != 0 && !arrived && !g_halting) {
      start_channel(i, speed_q8 > 0 ? 1 : -1, p.interval_q8, left);
    } else {
      left = now;
    }
    ch.base = left;
  }
}

}  // namespace

void start() {
  for (uint8_t i = 0; i < kCount; ++i) {
    pins::write(kPins(i).enable, true);
    pins::output(kPins(i).enable);
    pins::output(kPins(i).dir);
    pins::output(kPins(i).step.pin);
  }
  TCCR5B = 0;
  TCCR5A = 0;
  TIMSK5 = 0;
  TCNT5 = 0;
  TCCR5B = (1 << CS51) | (1 << CS50);  // normal mode, /64: 250 kHz
  static_assert(board::kCpuHz / 64 == kTickHz, "Timer5's prescaler gives kTickHz");
  kill();
}

void enable_drivers(bool on) {
  const uint8_t s = SREG;
  cli();
  for (uint8_t i = 0; i < kCount; ++i) pins::write(kPins(i).enable, !on);
  g_killed = !on;
  SREG = s;
  // a ramp left moving while the drivers were off would start at its speed
  if (on) {
    for (uint8_t i = 0; i < kCount; ++i) g_ch[i].rate.halt();
  }
}

// From the safety button's interrupt: the drivers off first (EN high), then the step trains.
// Unrolled into direct register writes: the safety button's latency (S5) is this.
void kill() {
  const uint8_t s = SREG;
  cli();
  for (uint8_t i = 0; i < kCount; ++i) pins::write(kPins(i).enable, true);
  TIMSK5 = 0;
  for (uint8_t i = 0; i < kCount; ++i) set_com(i, kComClear);
  TCCR5C = (1 << FOC5A) | (1 << FOC5B) | (1 << FOC5C);  // every STEP pin low
  for (uint8_t i = 0; i < kCount; ++i) set_com(i, 0);
  g_running = 0;
  g_killed = true;
  SREG = s;
}

// With interrupts off: channel i's train ends now. A step whose edge has risen (its compare
// matched) but whose interrupt has not yet run is made: the driver took it at the rising edge,
// so it is counted; the pulse is ended here.
template <uint8_t I>
inline void end_train() {
  Channel& c = g_ch[I].isr;
  const uint8_t flag = (uint8_t)(1 << ocie_bit(I));
  if (TIFR5 & flag) {
    --c.left;
    TIFR5 = flag;
  }
  TIMSK5 &= (uint8_t)~flag;
  set_com(I, kComClear);
  TCCR5C = (uint8_t)(1 << foc_bit(I));  // STEP low
  set_com(I, 0);
  g_running &= (uint8_t)~(1 << I);
}

template <uint8_t I>
inline void halt_train() {
  if ((g_running & (1 << I)) && g_ch[I].isr.interval >= g_ch[I].rate.stop_constants().start_stop_interval_ticks) end_train<I>();
}

void halt_trains() {
  const uint8_t s = SREG;
  cli();
  g_halting = true;
  halt_train<0>();
  halt_train<1>();
  halt_train<2>();
  SREG = s;
}

void resume() { g_halting = false; }
bool at_rest() { return g_running == 0; }

bool running(uint8_t i) { return g_running & (1 << i); }
namespace detail {
Rate* const kRate[kCount] = {&g_ch[0].rate, &g_ch[1].rate, &g_ch[2].rate};
}

// The three ISRs' counts read at once (one interrupt lock, not three), at constant addresses
void count() {
  static_assert(kCount == 3, "one count per channel below");
  uint16_t now0, now1, now2;
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
    now0 = g_ch[0].isr.left;
    now1 = g_ch[1].isr.left;
    now2 = g_ch[2].isr.left;
  }
  count_from(g_ch[0], now0);
  count_from(g_ch[1], now1);
  count_from(g_ch[2], now2);
}

void service(uint8_t ticks) {
  uint8_t bit = 1;
  for (uint8_t i = 0; i < kCount; ++i, bit = (uint8_t)(bit << 1)) {
    ChannelState& ch = g_ch[i];
    const int8_t stepping = count_made(ch, bit);
    if (g_killed) continue;  // the ramps as they were: the caller sees which were moving
    if (g_halting) ch.rate.quick_stop();
    const control::StepPlan p = ch.rate.plan(ticks, stepping);
    // Stopped and staying so: hand_over would change nothing (no edge, so the ISR's count
    // stands since count_made; a channel starts only in hand_over)
    if (stepping == 0 && p.interval_q8 == 0) continue;
    // A running speed command whose count is far from running out (it stops only at 0): at
    // most its interval is new, which is all hand_over would change for the ISR (its count set
    // back to kNoStop matters only once it falls below 0x8000, and then it is). Steps made
    // meanwhile are counted next time from base.
    if (stepping != 0 && p.interval_q8 != 0 && p.steps_left == Rate::kNoStop && ch.base >= 0x8000u) {
      if (p.interval_q8 != ch.handed_q8) {
        ch.handed_q8 = p.interval_q8;
        ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
          if (!g_killed) set_interval(i, ch.isr, p.interval_q8);
        }
      }
      continue;
    }
    // Nothing new for a running channel (its interval, and a count that already ends on the
    // target): the ISR goes on as it is (steps made meanwhile are counted next time from base).
    if (stepping != 0 && p.interval_q8 == ch.handed_q8 && p.steps_left == ch.base) continue;
    ch.handed_q8 = p.interval_q8;
    hand_over(i, bit, p, ch.rate.speed_q8());
  }
}

}  // namespace steppers
}  // namespace wmra

using namespace wmra;

ISR(TIMER5_COMPB_vect, ISR_NAKED) { steppers::on_edge<0>(); }  // J1
ISR(TIMER5_COMPC_vect, ISR_NAKED) { steppers::on_edge<1>(); }  // J5
ISR(TIMER5_COMPA_vect, ISR_NAKED) { steppers::on_edge<2>(); }  // J6
static_assert(board::kStepperJ1.step.channel == board::Channel::b && board::kStepperJ5.step.channel == board::Channel::c &&
                  board::kStepperJ6.step.channel == board::Channel::a,
              "the vectors above follow the board's channels");
