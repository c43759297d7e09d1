// virtual-nano/simavr/elf_symbols.h - the few things the virtual Nano reads from the firmware's ELF
// itself (libelf): where static RAM ends (for stack painting) and which function holds a
// flash address (to name where a long interrupts-off stretch began).
#ifndef ARTICULA_HIL_VNANO_ELF_SYMBOLS_H
#define ARTICULA_HIL_VNANO_ELF_SYMBOLS_H

#include <cstdint>
#include <string>
#include <vector>

namespace vnano {

class ElfSymbols {
 public:
  bool load(const std::string& path, std::string& error);

  // A symbol's value, or false.
  bool find(const std::string& name, uint32_t& value) const;

  // The end of static RAM in the data space (0x100.. on the ATmega328P): __heap_start,
  // else _end / __bss_end, else the end of the highest of .data, .bss, .noinit. 0 if none.
  uint32_t static_ram_end() const;
  const char* static_ram_end_source() const { return ram_end_source_.c_str(); }

  // "function+0x12" (demangled) for a byte address in flash, or "" when unknown.
  std::string function_at(uint32_t byte_address) const;

 private:
  struct Sym {
    std::string name;
    uint32_t value, size;
    bool function;
  };
  std::vector<Sym> syms_;
  uint32_t data_sections_end_ = 0;
  mutable std::string ram_end_source_;
};

}  // namespace vnano

#endif  // ARTICULA_HIL_VNANO_ELF_SYMBOLS_H
