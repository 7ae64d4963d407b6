#include "common/atomic_file.h"

#include <unistd.h>

#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/file_text.h"
#include "support/temp_dir.h"

namespace cmcsurf {
namespace {

using testing::slurp;

std::vector<std::string> entries(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    names.push_back(e.path().filename().string());
  return names;
}

TEST(IoAtomicFile, CommitWritesTargetAndLeavesNoTemporary) {
  TempDir tmp;
  const auto target = tmp / "out.txt";
  {
    AtomicWriter w(target);
    EXPECT_EQ(w.temp_path().parent_path(), target.parent_path());
    w.stream() << "hello\n";
    EXPECT_FALSE(std::filesystem::exists(target));  // nothing visible before commit
    w.commit();
  }
  EXPECT_EQ(slurp(target), "hello\n");
  EXPECT_EQ(entries(tmp.dir()), std::vector<std::string>{"out.txt"});
}

TEST(IoAtomicFile, DestroyWithoutCommitLeavesNothing) {
  TempDir tmp;
  const auto target = tmp / "out.txt";
  {
    AtomicWriter w(target);
    w.stream() << "partial";
    EXPECT_TRUE(std::filesystem::exists(w.temp_path()));
  }
  EXPECT_FALSE(std::filesystem::exists(target));
  EXPECT_TRUE(entries(tmp.dir()).empty());
}

TEST(IoAtomicFile, AbandonedWriteKeepsOldTarget) {
  TempDir tmp;
  const auto target = tmp / "out.txt";
  write_file_atomic(target, "old");
  {
    AtomicWriter w(target);
    w.stream() << "new but abandoned";
  }
  EXPECT_EQ(slurp(target), "old");
  write_file_atomic(target, std::string_view("new\0binary", 10));
  EXPECT_EQ(slurp(target), std::string("new\0binary", 10));
  EXPECT_EQ(entries(tmp.dir()).size(), 1u);
}

TEST(IoAtomicFile, OpenErrorNamesPathAndReason) {
  TempDir tmp;
  const auto target = tmp / "missing_dir" / "out.txt";
  try {
    write_file_atomic(target, "x");
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(target.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("No such file or directory"), std::string::npos) << msg;
  }
}

TEST(IoAtomicFile, RenameOntoDirectoryFailsAndCleansUp) {
  TempDir tmp;
  const auto target = tmp / "adir";
  std::filesystem::create_directory(target);
  EXPECT_THROW(write_file_atomic(target, "x"), std::runtime_error);
  EXPECT_EQ(entries(tmp.dir()), std::vector<std::string>{"adir"});
}

TEST(IoAtomicFile, EnsureDirectory) {
  TempDir tmp;
  const auto nested = tmp / "a" / "b" / "c";
  ensure_directory(nested);
  EXPECT_TRUE(std::filesystem::is_directory(nested));
  ensure_directory(nested);  // idempotent

  const auto file = tmp / "plain";
  write_file_atomic(file, "x");
  try {
    ensure_directory(file);
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("not a directory"), std::string::npos) << msg;
  }
  EXPECT_THROW(ensure_directory(file / "sub"), std::runtime_error);
}

// What a writer killed before its commit leaves: removed when its process is gone (or is this
// one); another live process's temporary, a user's file that merely looks like a temporary
// (thesis.tmp.99999.1) and every other file stay.
TEST(IoAtomicFile, StaleTemporariesAreRemoved) {
  TempDir tmp;
  const std::string mine = std::to_string(::getpid());
  const std::vector<std::string> gone = {"checkpoint.bin.cmcsurf-tmp." + mine + ".0",
                                         "field.vti.cmcsurf-tmp.2147483647.3"};
  const std::vector<std::string> kept = {"report.json.cmcsurf-tmp.1.0",  // pid 1 is alive
                                         "report.json", "notes.tmp", "x.tmp.a.b",
                                         "thesis.tmp.2147483647.1", "field.vti.tmp." + mine + ".0"};
  for (const auto& names : {gone, kept})
    for (const std::string& name : names) std::ofstream(tmp / name) << "partial";
  std::filesystem::create_directories(tmp / "sub.cmcsurf-tmp.2147483647.1");  // not a file
  EXPECT_EQ(remove_stale_temporaries(tmp.dir()), 2);
  for (const std::string& name : gone) EXPECT_FALSE(std::filesystem::exists(tmp / name)) << name;
  for (const std::string& name : kept) EXPECT_TRUE(std::filesystem::exists(tmp / name)) << name;
  EXPECT_TRUE(std::filesystem::exists(tmp / "sub.cmcsurf-tmp.2147483647.1"));
  EXPECT_EQ(remove_stale_temporaries(tmp / "missing"), 0);
}

TEST(IoTempDir, RemovedWithContents) {
  std::filesystem::path dir;
  {
    TempDir a, b;
    EXPECT_NE(a.dir(), b.dir());
    dir = a.dir();
    ensure_directory(a / "x" / "y");
    write_file_atomic(a / "x" / "y" / "f", "data");
  }
  EXPECT_FALSE(std::filesystem::exists(dir));
}

}  // namespace
}  // namespace cmcsurf
