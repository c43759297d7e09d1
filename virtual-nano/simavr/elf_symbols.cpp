// virtual-nano/simavr/elf_symbols.cpp - see elf_symbols.h.
#include "elf_symbols.h"

#include <cxxabi.h>
#include <fcntl.h>
#include <gelf.h>
#include <libelf.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace vnano {

namespace {
// avr-ld's data space starts at 0x800000 in the ELF's addresses.
const uint32_t kDataOffset = 0x800000;
const uint32_t kDataLimit = 0x810000;  // the EEPROM space starts here

std::string demangle(const std::string& name) {
  int status = 0;
  char* d = abi::__cxa_demangle(name.c_str(), nullptr, nullptr, &status);
  if (status != 0 || !d) return name;
  std::string s(d);
  std::free(d);
  return s;
}
}  // namespace

bool ElfSymbols::load(const std::string& path, std::string& error) {
  if (elf_version(EV_CURRENT) == EV_NONE) {
    error = "libelf is too old";
    return false;
  }
  const int fd = open(path.c_str(), O_RDONLY);
  if (fd < 0) {
    error = "cannot open " + path + ": " + std::strerror(errno);
    return false;
  }
  Elf* e = elf_begin(fd, ELF_C_READ, nullptr);
  if (!e || elf_kind(e) != ELF_K_ELF) {
    if (e) elf_end(e);
    close(fd);
    error = path + " is not an ELF file";
    return false;
  }
  GElf_Ehdr eh;
  if (!gelf_getehdr(e, &eh) || eh.e_machine != EM_AVR) {
    elf_end(e);
    close(fd);
    error = path + " is not an AVR ELF file";
    return false;
  }
  size_t shstrndx = 0;
  elf_getshdrstrndx(e, &shstrndx);
  Elf_Scn* scn = nullptr;
  while ((scn = elf_nextscn(e, scn)) != nullptr) {
    GElf_Shdr sh;
    if (!gelf_getshdr(scn, &sh)) continue;
    const char* sname = elf_strptr(e, shstrndx, sh.sh_name);
    if (sname && (!std::strcmp(sname, ".data") || !std::strcmp(sname, ".bss") || !std::strcmp(sname, ".noinit")) &&
        sh.sh_addr >= kDataOffset && sh.sh_addr < kDataLimit) {
      data_sections_end_ = std::max<uint32_t>(data_sections_end_, uint32_t(sh.sh_addr + sh.sh_size - kDataOffset));
    }
    if (sh.sh_type != SHT_SYMTAB || sh.sh_entsize == 0) continue;
    Elf_Data* data = elf_getdata(scn, nullptr);
    if (!data) continue;
    const size_t n = sh.sh_size / sh.sh_entsize;
    for (size_t i = 0; i < n; ++i) {
      GElf_Sym s;
      if (!gelf_getsym(data, int(i), &s)) continue;
      const char* name = elf_strptr(e, sh.sh_link, s.st_name);
      if (!name || !*name) continue;
      syms_.push_back({name, uint32_t(s.st_value), uint32_t(s.st_size), GELF_ST_TYPE(s.st_info) == STT_FUNC});
    }
  }
  elf_end(e);
  close(fd);
  std::sort(syms_.begin(), syms_.end(), [](const Sym& a, const Sym& b) { return a.value < b.value; });
  return true;
}

bool ElfSymbols::find(const std::string& name, uint32_t& value) const {
  for (const Sym& s : syms_)
    if (s.name == name) {
      value = s.value;
      return true;
    }
  return false;
}

uint32_t ElfSymbols::static_ram_end() const {
  for (const char* n : {"__heap_start", "_end", "__bss_end", "__noinit_end"}) {
    uint32_t v = 0;
    if (find(n, v) && v >= kDataOffset && v < kDataLimit) {
      ram_end_source_ = n;
      return v - kDataOffset;
    }
  }
  ram_end_source_ = data_sections_end_ ? "sections" : "none";
  return data_sections_end_;
}

std::string ElfSymbols::function_at(uint32_t addr) const {
  const Sym* best = nullptr;
  for (const Sym& s : syms_) {
    if (s.value >= kDataOffset) break;
    if (!s.function || s.value > addr) continue;
    if (s.size && addr >= s.value + s.size) continue;
    if (!best || s.value >= best->value) best = &s;
  }
  if (!best) return "";
  char off[32];
  std::snprintf(off, sizeof off, "+0x%x", unsigned(addr - best->value));
  return demangle(best->name) + off;
}

}  // namespace vnano
