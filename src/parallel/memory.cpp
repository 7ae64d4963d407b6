#include "parallel/memory.h"

#include <sys/resource.h>

#include <fstream>
#include <sstream>

#include <fmt/format.h>

namespace cmcsurf {

namespace {

// A "Key:   123 kB" line of a /proc file, in bytes (0 when absent).
std::uint64_t proc_kb(const char* path, const std::string& key) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key + ":", 0) == 0) {
      std::istringstream fields(line.substr(key.size() + 1));
      std::uint64_t kb = 0;
      fields >> kb;
      return kb * 1024;
    }
  return 0;
}

// A cgroup file holding one number ("max" or missing: none).
bool read_number(const std::string& path, std::uint64_t& value) {
  std::ifstream in(path);
  std::string text;
  if (!(in >> text) || text == "max") return false;
  try {
    value = std::stoull(text);
  } catch (const std::exception&) {
    return false;
  }
  return true;
}

// This process's cgroup (v2: "0::/path"; v1: the memory controller's line).
std::string cgroup_dir() {
  std::ifstream in("/proc/self/cgroup");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("0::", 0) == 0) return "/sys/fs/cgroup" + line.substr(3);
    const auto memory = line.find(":memory:");
    if (memory != std::string::npos)
      return "/sys/fs/cgroup/memory" + line.substr(memory + 8);
  }
  return {};
}

void take(MemoryHeadroom& h, std::uint64_t bytes, const char* source) {
  if (bytes < h.bytes) h = {bytes, source};
}

}  // namespace

MemoryHeadroom memory_headroom() {
  MemoryHeadroom h;
  rlimit as{};
  if (::getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) {
    const std::uint64_t mapped = proc_kb("/proc/self/status", "VmSize");
    take(h, as.rlim_cur > mapped ? as.rlim_cur - mapped : 0, "RLIMIT_AS");
  }
  if (const std::string dir = cgroup_dir(); !dir.empty()) {
    std::uint64_t limit = 0, used = 0;
    if (read_number(dir + "/memory.max", limit)) {  // v2
      read_number(dir + "/memory.current", used);
      take(h, limit > used ? limit - used : 0, "cgroup memory.max");
    } else if (read_number(dir + "/memory.limit_in_bytes", limit) && limit < (1ull << 60)) {  // v1
      read_number(dir + "/memory.usage_in_bytes", used);
      take(h, limit > used ? limit - used : 0, "cgroup memory.limit_in_bytes");
    }
  }
  if (const std::uint64_t available = proc_kb("/proc/meminfo", "MemAvailable"); available > 0)
    take(h, available, "MemAvailable");
  return h;
}

std::string format_bytes(std::uint64_t bytes) {
  if (bytes >= (1ull << 30)) return fmt::format("{:.1f} GB", double(bytes) / 1e9);
  return fmt::format("{:.0f} MB", double(bytes) / 1e6);
}

}  // namespace cmcsurf
