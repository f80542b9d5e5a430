// What the gvsd executable itself must carry, read from its ELF file.
#include <elf.h>
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

// DT_FLAGS & DF_BIND_NOW or DT_FLAGS_1 & DF_1_NOW in the dynamic section
// (what `readelf -d` prints as "BIND_NOW" / "Flags: NOW").
bool binds_now(const std::vector<char>& elf) {
  Elf64_Ehdr eh;
  if (elf.size() < sizeof eh) return false;
  std::memcpy(&eh, elf.data(), sizeof eh);
  if (std::memcmp(eh.e_ident, ELFMAG, SELFMAG) != 0 || eh.e_ident[EI_CLASS] != ELFCLASS64) return false;
  for (int i = 0; i < eh.e_phnum; ++i) {
    Elf64_Phdr ph;
    const std::size_t at = eh.e_phoff + static_cast<std::size_t>(i) * eh.e_phentsize;
    if (at + sizeof ph > elf.size()) return false;
    std::memcpy(&ph, elf.data() + at, sizeof ph);
    if (ph.p_type != PT_DYNAMIC) continue;
    for (std::size_t d = ph.p_offset;
         d + sizeof(Elf64_Dyn) <= ph.p_offset + ph.p_filesz && d + sizeof(Elf64_Dyn) <= elf.size();
         d += sizeof(Elf64_Dyn)) {
      Elf64_Dyn dyn;
      std::memcpy(&dyn, elf.data() + d, sizeof dyn);
      if (dyn.d_tag == DT_FLAGS && (dyn.d_un.d_val & DF_BIND_NOW) != 0) return true;
      if (dyn.d_tag == DT_FLAGS_1 && (dyn.d_un.d_val & DF_1_NOW) != 0) return true;
      if (dyn.d_tag == DT_NULL) break;
    }
  }
  return false;
}

}  // namespace

// Bound lazily, a real-time thread's first call of a library function
// (clock_nanosleep, fwrite) runs the dynamic linker's symbol lookup on the
// real-time path and may fault; gvsd is linked with -z now.
TEST(Gvsd, BinaryBindsEveryLibrarySymbolAtLoad) {
  std::ifstream in(GVSD_BINARY, std::ios::binary);
  ASSERT_TRUE(in) << "cannot read " << GVSD_BINARY;
  const std::vector<char> elf((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_TRUE(binds_now(elf)) << GVSD_BINARY << " has neither DF_BIND_NOW nor DF_1_NOW (link with -z now)";
}
