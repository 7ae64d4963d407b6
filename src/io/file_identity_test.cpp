#include "io/file_identity.h"

#include <gtest/gtest.h>

#include <fstream>

#include "model/run_options.h"

namespace cmcsurf {
namespace {

namespace fs = std::filesystem;

TEST(FileIdentity, SameFileByAnyNameIsRefused) {
  const fs::path dir = fs::temp_directory_path() / "cmcsurf_file_identity_test";
  fs::remove_all(dir);
  fs::create_directories(dir / "sub");
  std::ofstream(dir / "in.vti") << "x";
  std::ofstream(dir / "other.stl") << "y";
  fs::create_symlink(dir / "in.vti", dir / "link.stl");
  const std::vector<FileRole> reads = {{dir / "in.vti", "--from"}};
  // Another spelling, a symlink: refused; a different file or one not there yet: accepted.
  EXPECT_THROW(check_outputs_are_not_inputs(reads, {{dir / "sub" / ".." / "in.vti", "--out"}}),
               OptionError);
  EXPECT_THROW(check_outputs_are_not_inputs(reads, {{dir / "link.stl", "--out"}}), OptionError);
  EXPECT_NO_THROW(check_outputs_are_not_inputs(reads, {{dir / "other.stl", "--out"}}));
  EXPECT_NO_THROW(check_outputs_are_not_inputs(reads, {{dir / "new.stl", "--out"}}));
  try {
    check_outputs_are_not_inputs(reads, {{dir / "other.stl", "--out"},
                                         {dir / "link.stl", "--out's report"}});
    ADD_FAILURE() << "not refused";
  } catch (const OptionError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("--out's report"), std::string::npos) << m;
    EXPECT_NE(m.find("--from"), std::string::npos) << m;
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace cmcsurf
