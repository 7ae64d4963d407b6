#include "io/json_file.h"

#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "common/atomic_file.h"
#include "support/read_json.h"
#include "support/file_text.h"
#include "support/temp_dir.h"

namespace cmcsurf {
namespace {

using testing::slurp;

TEST(IoJson, RoundTripPrettyWithTrailingNewline) {
  TempDir tmp;
  const nlohmann::json report = {
      {"surface", "P"},
      {"n", 128},
      {"volume_fraction", 0.1 + 0.2},
      {"energies", {1.0 / 3.0, 2e-300, -5.5}},
      {"nested", {{"ok", true}, {"none", nullptr}}},
  };
  const auto path = tmp / "report.json";
  write_json_atomic(path, report);
  const std::string text = slurp(path);
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n');
  EXPECT_EQ(text, report.dump(2) + "\n");
  EXPECT_NE(text.find("\n  \"n\": 128"), std::string::npos);  // indent 2
  EXPECT_EQ(read_json(path), report);                          // doubles exact
}

TEST(IoJson, NonFiniteNumbersBecomeNull) {
  TempDir tmp;
  const auto path = tmp / "nan.json";
  write_json_atomic(path, {{"nan", std::numeric_limits<double>::quiet_NaN()},
                           {"inf", std::numeric_limits<double>::infinity()}});
  const auto back = read_json(path);
  EXPECT_TRUE(back.at("nan").is_null());
  EXPECT_TRUE(back.at("inf").is_null());
}

TEST(IoJson, ReadErrorsNameTheFile) {
  TempDir tmp;
  const auto missing = tmp / "missing.json";
  try {
    read_json(missing);
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(missing.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("No such file"), std::string::npos) << msg;
  }
  const auto bad = tmp / "bad.json";
  write_file_atomic(bad, "{\n  \"a\": 1,\n  \"b\": \n}\n");
  try {
    read_json(bad);
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(bad.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("line 4"), std::string::npos) << msg;
  }
}

TEST(IoJson, ReadJsonFileReadsWhatWasWritten) {
  TempDir tmp;
  const nlohmann::json report = {{"volume_fraction", 0.1 + 0.2}, {"tiny", 2e-300}};
  const auto path = tmp / "report.json";
  write_json_atomic(path, report);
  EXPECT_EQ(read_json_file(path), report);  // doubles exact
}

// Each message starts with the path, so a resume or a command names the file it could not use.
TEST(IoJson, ReadJsonFileErrorsNameTheFile) {
  TempDir tmp;
  auto message = [](const std::filesystem::path& p) -> std::string {
    try {
      read_json_file(p);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "no exception";
  };
  const auto missing = tmp / "missing.json";
  EXPECT_EQ(message(missing), missing.string() + ": cannot open");
  const auto bad = tmp / "bad.json";
  write_file_atomic(bad, "{\n  \"a\": 1,\n  \"b\": \n}\n");
  const std::string parse = message(bad);
  EXPECT_EQ(parse.rfind(bad.string() + ": not valid JSON: ", 0), 0u) << parse;
  EXPECT_NE(parse.find("line 4"), std::string::npos) << parse;
  const std::string dir = message(tmp.dir());
  EXPECT_NE(dir.find("is not a regular file (a directory)"), std::string::npos) << dir;
}

TEST(IoJson, InvalidUtf8IsAnError) {
  TempDir tmp;
  const auto path = tmp / "bad_utf8.json";
  EXPECT_THROW(write_json_atomic(path, {{"s", std::string("\xff\xfe")}}), std::runtime_error);
  EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace cmcsurf
