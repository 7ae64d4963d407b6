// The fuzz corpus as a regression test in every build (no clang): each file of
// fuzz/corpus/<target>/ goes through the same function the libFuzzer binary calls
// (fuzz/<target>_fuzz.cpp). A file named ok-* must parse, bad-* must be refused with the
// reader's documented error; any other file (what the fuzzer kept, minimised crashes) may do
// either. An undocumented exception or a failed property fails the test; a memory error
// aborts it (and is reported as one in the sanitizer build).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz_target.h"

namespace cmcsurf::fuzz {
namespace {

namespace fs = std::filesystem;

std::vector<unsigned char> read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(FuzzCorpus, EveryTargetHasSeeds) {
  ASSERT_FALSE(targets().empty());
  for (const Target& t : targets()) {
    const fs::path dir = fs::path(CMCSURF_FUZZ_CORPUS) / t.name;
    ASSERT_TRUE(fs::is_directory(dir)) << dir;
    int ok = 0, bad = 0;
    for (const auto& e : fs::directory_iterator(dir)) {
      const std::string name = e.path().filename().string();
      ok += name.starts_with("ok-");
      bad += name.starts_with("bad-");
    }
    EXPECT_GE(ok, 1) << t.name << ": no ok-* seed (a file the reader must take)";
    EXPECT_GE(bad, 1) << t.name << ": no bad-* seed (a file the reader must refuse)";
  }
}

TEST(FuzzCorpus, EveryFileParsesOrIsRefused) {
  for (const Target& t : targets()) {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(fs::path(CMCSURF_FUZZ_CORPUS) / t.name))
      if (e.is_regular_file()) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const fs::path& file : files) {
      SCOPED_TRACE(file.string());
      const std::vector<unsigned char> bytes = read_bytes(file);
      Outcome outcome = Outcome::refused;
      ASSERT_NO_THROW(outcome = t.run(bytes));
      const std::string name = file.filename().string();
      if (name.starts_with("ok-")) {
        EXPECT_EQ(outcome, Outcome::parsed);
      } else if (name.starts_with("bad-")) {
        EXPECT_EQ(outcome, Outcome::refused);
      }
    }
  }
}

}  // namespace
}  // namespace cmcsurf::fuzz
