// What the front ends say about input files before reading them: the one
// check that a path names a readable file (input_file.h), and file bytes
// quoted in an error only as printable text of bounded length
// (printable_text.h).
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "rayscope/input_file.h"
#include "rayscope/printable_text.h"

namespace {

namespace fs = std::filesystem;
using rayscope::input_file_problem;
using rayscope::kMaxQuotedBytes;
using rayscope::printable_text;

TEST(PrintableText, ControlBytesAreEscapedAndTextKept) {
  EXPECT_EQ(printable_text("plain words 1.5e3 {}[]"), "plain words 1.5e3 {}[]");
  EXPECT_EQ(printable_text(std::string("a\0b", 3)), "a\\x00b");
  EXPECT_EQ(printable_text("\x1b[31mred\n\r\t\x7f"), "\\x1B[31mred\\x0A\\x0D\\x09\\x7F");
  // Valid UTF-8 (a name in any script) is kept; stray or cut sequences are not.
  EXPECT_EQ(printable_text("Gr\xc3\xbc\xc3\x9f \xe6\x97\xa5"), "Gr\xc3\xbc\xc3\x9f \xe6\x97\xa5");
  EXPECT_EQ(printable_text("\xc3(\x80\xff"), "\\xC3(\\x80\\xFF");
  EXPECT_EQ(printable_text("ab\xe6\x97"), "ab\\xE6\\x97");
}

TEST(PrintableText, LongInputIsCutAndItsRealLengthGiven) {
  const std::string bytes(65536, 'x');
  const std::string t = printable_text(bytes);
  EXPECT_EQ(t, std::string(kMaxQuotedBytes, 'x') + "... (65536 bytes)");
  // Every byte escaped still shows at most kMaxQuotedBytes of the input.
  const std::string nuls(1000, '\0');
  EXPECT_EQ(printable_text(nuls, 4), "\\x00\\x00\\x00\\x00... (1000 bytes)");
  // A UTF-8 sequence cut by the limit is escaped, not split.
  EXPECT_EQ(printable_text("a\xc3\xbc", 2), "a\\xC3... (3 bytes)");
  // Random bytes: nothing below 0x20 or at 0x7F survives.
  std::string random(4096, '\0');
  unsigned v = 31;
  for (char& c : random) c = char((v = v * 1103515245u + 12345u) >> 16);
  for (char c : printable_text(random, random.size()))
    EXPECT_TRUE(static_cast<unsigned char>(c) >= 0x20 && c != 0x7F) << int(c);
}

class InputFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("rayscope_input_files_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(InputFiles, EachProblemInWords) {
  const fs::path file = dir_ / "scene.json";
  std::ofstream(file) << "{}";
  EXPECT_EQ(input_file_problem(file), "");
  EXPECT_EQ(input_file_problem(dir_ / "missing.json"), "file not found");
  EXPECT_EQ(input_file_problem(dir_), "is a directory, not a file");
  EXPECT_EQ(input_file_problem("/dev/null"), "is not a regular file");
  // A link to a file is the file; a dangling link and a loop say what they are
  // (a loop was reported as "file not found").
  fs::create_symlink(file, dir_ / "link.json");
  EXPECT_EQ(input_file_problem(dir_ / "link.json"), "");
  fs::create_symlink(dir_ / "nowhere.json", dir_ / "dangling.json");
  EXPECT_EQ(input_file_problem(dir_ / "dangling.json"),
            "is a symbolic link to a file that does not exist");
  fs::create_symlink(dir_ / "b.json", dir_ / "a.json");
  fs::create_symlink(dir_ / "a.json", dir_ / "b.json");
  EXPECT_EQ(input_file_problem(dir_ / "a.json"), "is a loop of symbolic links");
  EXPECT_EQ(input_file_problem(dir_ / "a.json" / "x.obj"), "is a loop of symbolic links");
}

}  // namespace
