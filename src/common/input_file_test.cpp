#include "common/input_file.h"

#include <sys/stat.h>

#include <fstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "io/checkpoint.h"
#include "io/vti.h"
#include "support/temp_dir.h"

namespace cmcsurf {
namespace {

// require_regular_file's message for the path, "" if it passes.
std::string why(const std::filesystem::path& p) {
  try {
    require_regular_file(p, "test file");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(InputFile, OnlyRegularFilesPass) {
  TempDir tmp("cmcsurf-input");
  std::ofstream(tmp / "plain") << "x";
  EXPECT_EQ(why(tmp / "plain"), "");
  EXPECT_EQ(why(tmp / "missing"), "");  // the caller's open says it is missing
  std::filesystem::create_symlink(tmp / "plain", tmp / "link");
  EXPECT_EQ(why(tmp / "link"), "");
  ASSERT_EQ(::mkfifo((tmp / "fifo").c_str(), 0600), 0);
  const std::string fifo = why(tmp / "fifo");
  EXPECT_NE(fifo.find("test file '" + (tmp / "fifo").string() + "'"), std::string::npos) << fifo;
  EXPECT_NE(fifo.find("not a regular file (a FIFO)"), std::string::npos) << fifo;
  EXPECT_NE(why(tmp.dir()).find("(a directory)"), std::string::npos);
}

TEST(InputFile, ReadersRefuseAFifoWithoutOpeningIt) {
  // Opening a FIFO for reading blocks until a writer comes: a hang, were it opened.
  TempDir tmp("cmcsurf-input");
  ASSERT_EQ(::mkfifo((tmp / "field.vti").c_str(), 0600), 0);
  EXPECT_THROW(read_vti(tmp / "field.vti"), std::runtime_error);
  ASSERT_EQ(::mkfifo((tmp / "checkpoint.bin").c_str(), 0600), 0);
  try {
    read_checkpoint(tmp / "checkpoint.bin");
    ADD_FAILURE() << "read a FIFO";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace cmcsurf
