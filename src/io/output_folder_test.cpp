#include "io/output_folder.h"

#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "support/file_text.h"
#include "support/temp_dir.h"

namespace cmcsurf {
namespace {

namespace fs = std::filesystem;

using testing::spit;

std::string message_of(const fs::path& dir, const ClaimOptions& o, bool* usage = nullptr) {
  try {
    claim_output_folder(dir, o);
  } catch (const FolderRefused& e) {
    if (usage) *usage = e.usage();
    return e.what();
  }
  return {};
}

TEST(OutputFolder, NewAndEmptyFoldersAreClaimedAndMarked) {
  TempDir tmp;
  {
    const FolderClaim c = claim_output_folder(tmp / "a" / "b", {});
    EXPECT_TRUE(c.held());
    EXPECT_TRUE(fs::exists(tmp / "a" / "b" / kFolderMarker));
  }
  fs::create_directory(tmp / "empty");
  EXPECT_TRUE(claim_output_folder(tmp / "empty", {}).held());
  EXPECT_TRUE(is_cmcsurf_folder(tmp / "empty"));
  // Nothing but the marker is left behind by the writability probe.
  EXPECT_EQ(std::distance(fs::directory_iterator(tmp / "empty"), {}), 1);
}

TEST(OutputFolder, ForeignFoldersAreRefusedUnlessForced) {
  TempDir tmp;
  fs::create_directory(tmp / "d");
  spit(tmp / "d" / "report.json", R"({"mine":1})");
  spit(tmp / "d" / "surface.obj", "x");
  bool usage = false;
  const std::string why = message_of(tmp / "d", {.option = "--out"}, &usage);
  EXPECT_TRUE(usage);
  EXPECT_NE(why.find("--out '" + (tmp / "d").string() + "'"), std::string::npos) << why;
  EXPECT_NE(why.find("report.json, surface.obj"), std::string::npos) << why;
  EXPECT_NE(why.find("--force"), std::string::npos) << why;
  EXPECT_FALSE(fs::exists(tmp / "d" / kFolderMarker));  // untouched
  EXPECT_TRUE(claim_output_folder(tmp / "d", {.force = true}).held());
  // A file is not a folder, and the root never is an output folder.
  spit(tmp / "f", "x");
  EXPECT_NE(message_of(tmp / "f", {}, &usage).find("not a folder"), std::string::npos);
  EXPECT_TRUE(usage);
  EXPECT_NE(message_of("/", {.force = true}, &usage).find("root"), std::string::npos);
  EXPECT_TRUE(usage);
}

TEST(OutputFolder, FoldersWrittenBeforeMarkersAreRecognised) {
  TempDir tmp;
  fs::create_directories(tmp / "run");
  spit(tmp / "run" / "report.json", R"({"version":"0.1.0","build":{},"parameters":{}})");
  EXPECT_TRUE(is_cmcsurf_folder(tmp / "run"));
  fs::create_directories(tmp / "ck");
  spit(tmp / "ck" / "checkpoint.bin", "CMCSCKPT and the rest");
  EXPECT_TRUE(is_cmcsurf_folder(tmp / "ck"));
  fs::create_directories(tmp / "other");
  spit(tmp / "other" / "report.json", R"({"version":"1"})");
  spit(tmp / "other" / "checkpoint.bin", "CMCSCKP");
  EXPECT_FALSE(is_cmcsurf_folder(tmp / "other"));
}

TEST(OutputFolder, OneWriterAtATime) {
  TempDir tmp;
  FolderClaim first = claim_output_folder(tmp / "d", {});
  // flock locks belong to the open file: another process is refused while this one holds it.
  const pid_t child = ::fork();
  if (child == 0) {
    bool usage = true;
    const std::string why = message_of(tmp / "d", {}, &usage);
    ::_exit(!usage && why.find("another cmcsurf process") != std::string::npos ? 0 : 1);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  first.release();
  const pid_t again = ::fork();
  if (again == 0) ::_exit(claim_output_folder(tmp / "d", {}).held() ? 0 : 1);
  ASSERT_EQ(::waitpid(again, &status, 0), again);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
}

TEST(OutputFolder, AnEarlierMembersFolderGoesOnlyWhenNothingElseIsInIt) {
  TempDir tmp;
  claim_output_folder(tmp / "m", {});
  EXPECT_TRUE(remove_folder_if_only_ours(tmp / "m"));
  EXPECT_FALSE(fs::exists(tmp / "m"));
  claim_output_folder(tmp / "n", {});
  spit(tmp / "n" / "notes.txt", "mine");
  EXPECT_FALSE(remove_folder_if_only_ours(tmp / "n"));
  EXPECT_TRUE(fs::exists(tmp / "n" / "notes.txt"));
}

}  // namespace
}  // namespace cmcsurf
