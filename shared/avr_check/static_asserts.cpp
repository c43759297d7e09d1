// The assumptions the core makes about the ATmega328P with avr-gcc 5.4, stated where the
// compiler checks them (ArduinoJson's extras/conf_test/avr.cpp does the same).
#include <articula/articula.h>

#ifndef __AVR__
#error "static_asserts.cpp is for the AVR build"
#endif

using namespace articula;

// The C-library view of the machine: 16-bit int, 32-bit double.
static_assert(sizeof(int) == 2, "int is 16 bits on AVR");
static_assert(sizeof(long) == 4, "long is 32 bits on AVR");
static_assert(sizeof(double) == 4, "double is float on AVR: the core must not need more");
static_assert(sizeof(float) == 4, "float is IEEE single");
static_assert(sizeof(int32_t) == 4 && sizeof(int64_t) == 8, "fixed-width integers exist");
static_assert(sizeof(void*) == 2, "pointers are 16 bits");

// Exact arithmetic in actuation.h: angles and step counts in int32, products in int64.
static_assert(kMaxAbsMillideg <= 2147483647L / 2, "a difference of two angles fits int32");
static_assert(1000000000LL * 2147483647LL < 9223372036854775807LL / 2, "angle * steps-per-turn fits int64 twice");

// Enums the codec and the state store in one byte.
static_assert(sizeof(Status) == 1, "Status is one byte");
static_assert(sizeof(CommandType) == 1, "CommandType is one byte");
static_assert(sizeof(DhParam) == 1, "DhParam is one byte");
static_assert(kStatusCount <= 255, "status codes fit a byte");

// Line lengths are counted in uint8_t, with room for a CR and a NUL.
static_assert(kMaxLineLength + 2 <= 255, "a line and its terminators fit uint8_t");

// What the firmware keeps in RAM (2,048 bytes in all): the model, the actuation, the state.
static_assert(sizeof(Model<float, 3, 4>) <= 256, "the MK2 model fits an eighth of the RAM");
static_assert(sizeof(Actuation<float, 3>) <= 160, "the MK2 actuation is small");
static_assert(sizeof(MotorState<3>) == 24, "three commanded angles and three step counts");
static_assert(sizeof(LineAssembler) <= kMaxLineLength + 8, "one line buffer");

// Step timing in motion.h: the interrupt's state is small, and the fixed-point limits hold.
static_assert(sizeof(StepProfile) == 30, "seven uint32 and two flags");
static_assert(sizeof(LineStepper<3>) == 34, "the line of three motors");
static_assert(2ULL * (kMaxStepTicks << 8) + 4ULL * (1ULL << 25) + 1 < 4294967296ULL,
              "2C + r of the recurrence fits a uint32 (ramp levels stay below 2^24, margin 2x)");
static_assert((uint64_t(kMaxTickHz) * kMaxTickHz << 16) >> 16 == uint64_t(kMaxTickHz) * kMaxTickHz,
              "2^16 f^2 fits a uint64");

// A C++11 constexpr body is a single return statement in GCC 5.4: the core has none that
// are longer, and this one shows the compiler accepts the form it uses.
constexpr int twice(int x) { return 2 * x; }
static_assert(twice(21) == 42, "C++11 constexpr");
