// ELF32 header and section table, read as the System V ABI's ELF format defines them (e_shoff at byte 32, e_shentsize,
// e_shnum and e_shstrndx at 46, 48 and 50; a section header's sh_name, sh_offset and sh_size at 0, 16 and 20).
// Only what elf_image.hpp needs: every offset is checked against the file's size, nothing is trusted.
#include "elf_image.hpp"

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

namespace lashid::sim::detail {

namespace {

constexpr std::size_t kHeaderSize = 52;                // ELF32 header
constexpr std::size_t kSectionHeaderSize = 40;         // ELF32 section header
constexpr std::size_t kMaxImageBytes = std::size_t{64} << 20;  // larger than any Cortex-M image; a bound on what is read
constexpr const char* kMachineSection = ".lashid.machine";
constexpr const char* kPlantSection = ".lashid.plant";

std::uint32_t le32(const std::vector<unsigned char>& b, std::size_t at) {
  return static_cast<std::uint32_t>(b[at]) | static_cast<std::uint32_t>(b[at + 1]) << 8 |
         static_cast<std::uint32_t>(b[at + 2]) << 16 | static_cast<std::uint32_t>(b[at + 3]) << 24;
}
std::uint16_t le16(const std::vector<unsigned char>& b, std::size_t at) {
  return static_cast<std::uint16_t>(b[at] | b[at + 1] << 8);
}

bool arm_elf_header(const std::vector<unsigned char>& b) {
  constexpr int kEmArm = 40;
  return b.size() >= kHeaderSize && b[0] == 0x7f && b[1] == 'E' && b[2] == 'L' && b[3] == 'F' && b[4] == 1 /* 32-bit */
         && b[5] == 1 /* little-endian */ && le16(b, 18) == kEmArm;
}

std::vector<unsigned char> read_image(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  in.seekg(0, std::ios::end);
  const auto size = static_cast<std::size_t>(std::max<std::streamoff>(in.tellg(), 0));
  if (size > kMaxImageBytes) return {};
  in.seekg(0);
  std::vector<unsigned char> bytes(size);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size))) return {};
  return bytes;
}

// A NUL-terminated string at `at` within `b`, or nullopt if it runs past `end`.
std::optional<std::string> string_at(const std::vector<unsigned char>& b, std::size_t at, std::size_t end) {
  std::string s;
  for (std::size_t i = at; i < end && i < b.size(); ++i) {
    if (b[i] == 0) return s;
    s.push_back(static_cast<char>(b[i]));
  }
  return std::nullopt;
}

}  // namespace

bool is_arm_elf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<unsigned char> header(kHeaderSize);
  if (!in.read(reinterpret_cast<char*>(header.data()), static_cast<std::streamsize>(header.size()))) return false;
  return arm_elf_header(header);
}

namespace {

// The NUL-terminated string in the image's section `wanted`.
std::optional<std::string> section_string(const std::string& path, const char* wanted) {
  const std::vector<unsigned char> b = read_image(path);
  if (!arm_elf_header(b)) return std::nullopt;
  const std::size_t shoff = le32(b, 32), entsize = le16(b, 46), count = le16(b, 48), names = le16(b, 50);
  if (entsize < kSectionHeaderSize || names >= count || shoff + count * entsize > b.size()) return std::nullopt;
  const auto section = [&](std::size_t i) { return shoff + i * entsize; };
  const std::size_t names_offset = le32(b, section(names) + 16), names_size = le32(b, section(names) + 20);
  if (names_offset + names_size > b.size()) return std::nullopt;
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t name = le32(b, section(i));
    if (name >= names_size || string_at(b, names_offset + name, names_offset + names_size) != wanted) continue;
    const std::size_t offset = le32(b, section(i) + 16), size = le32(b, section(i) + 20);
    if (offset + size > b.size()) return std::nullopt;
    return string_at(b, offset, offset + size);
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::string> elf_damage(const std::string& path) {
  const std::vector<unsigned char> b = read_image(path);
  if (!arm_elf_header(b)) return "not an ARM ELF image, or larger than 64 MiB";
  // Program headers (e_phoff at 28, e_phentsize at 42, e_phnum at 44; p_type, p_offset and p_filesz at 0, 4 and 16):
  // what QEMU loads. A segment whose bytes lie past the end of the file boots into a lockup.
  constexpr std::size_t kProgramHeaderSize = 32;
  constexpr std::uint32_t kPtLoad = 1;
  const std::size_t phoff = le32(b, 28), phentsize = le16(b, 42), phnum = le16(b, 44);
  if (phnum == 0) return "it has no program headers: nothing to load";
  if (phentsize < kProgramHeaderSize || phoff + phnum * phentsize > b.size()) {
    return "its program header table lies past the end of the file (cut short?)";
  }
  for (std::size_t i = 0; i < phnum; ++i) {
    const std::size_t at = phoff + i * phentsize;
    if (le32(b, at) != kPtLoad) continue;
    const std::uint64_t end = std::uint64_t{le32(b, at + 4)} + le32(b, at + 16);
    if (end > b.size()) {
      return fmt::format("its segment {} ends at byte {}, past the end of the file ({} bytes): cut short?", i, end,
                         b.size());
    }
  }
  // The section table (e_shoff at 32; 0 when there is none) holds the machine and plant tags.
  const std::size_t shoff = le32(b, 32), shentsize = le16(b, 46), shnum = le16(b, 48);
  if (shoff != 0 && shoff + shnum * shentsize > b.size()) {
    return "its section table lies past the end of the file (cut short?)";
  }
  return std::nullopt;
}

std::optional<std::string> elf_machine_tag(const std::string& path) { return section_string(path, kMachineSection); }

std::optional<std::string> elf_plant_tag(const std::string& path) { return section_string(path, kPlantSection); }

}  // namespace lashid::sim::detail
