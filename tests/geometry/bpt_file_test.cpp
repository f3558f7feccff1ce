// Specification of the .bpt loader: the teapot loads, and every kind of bad input becomes an
// InputError naming the file and line (docs/design.md, invariant 6).
#include <gtest/gtest.h>
#include <filesystem>
#include <fstream>
#include "core/error.h"
#include "geometry/bezier_patch.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {

TEST(BptFile, LoadsTheTeapot) {
  const auto patches = test::loadTeapot();
  ASSERT_EQ(patches.size(), 32u);
  // First patch, first control point: point 1 of the file, "1.4,0.0,2.4".
  EXPECT_EQ(patches[0][0], (Vec3{1.4f, 0.0f, 2.4f}));
  // Second patch starts with index 4, shared with the first patch's last column.
  EXPECT_EQ(patches[1][0], patches[0][3]);
}

class BptFileErrors : public ::testing::Test {
 protected:
  std::string write(const std::string& content) {
    const auto dir = std::filesystem::temp_directory_path() / "rayes_dicing_test";
    std::filesystem::create_directories(dir);
    const std::string path = (dir / (std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + ".bpt")).string();
    std::ofstream(path) << content;
    return path;
  }
  // The line named by the InputError thrown for `content`.
  std::string errorPlace(const std::string& content) {
    const std::string path = write(content);
    try {
      loadBezierPatchFile(path);
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path);
      return e.place();
    }
    ADD_FAILURE() << "no InputError for:\n" << content;
    return "";
  }
  static std::string indices(const std::string& last) { return "1,1,1,1,1,1,1,1,1,1,1,1,1,1,1," + last + "\n"; }
};

TEST_F(BptFileErrors, MissingFile) {
  EXPECT_THROW(loadBezierPatchFile("/nonexistent/rayes/teapot.bpt"), InputError);
}

TEST_F(BptFileErrors, ValidSmallFileLoads) {
  const std::string path = write("1\n" + indices("2") + "\n2\n0,0,0\n1, 2 ,3\n");
  const auto p = loadBezierPatchFile(path);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(p[0][15], (Vec3{1, 2, 3}));
}

TEST_F(BptFileErrors, BadNumbers) {
  EXPECT_EQ(errorPlace("x\n"), "line 1");
  EXPECT_EQ(errorPlace("1\n" + indices("2a") + "2\n0,0,0\n1,2,3\n"), "line 2");
  EXPECT_EQ(errorPlace("1\n" + indices("2") + "2\n0,0,0\n1,zz,3\n"), "line 5");
  EXPECT_EQ(errorPlace("1\n" + indices("2") + "2\n0,0,0\n1,nan,3\n"), "line 5");
  EXPECT_EQ(errorPlace("1\n" + indices("2") + "2\n0,0,0\n1,2\n"), "line 5");
  EXPECT_EQ(errorPlace("1\n" + indices("2,3") + "2\n0,0,0\n1,2,3\n"), "line 2");
  EXPECT_EQ(errorPlace("-1\n"), "line 1");
}

TEST_F(BptFileErrors, IndexOutOfRange) {
  EXPECT_EQ(errorPlace("1\n" + indices("3") + "2\n0,0,0\n1,2,3\n"), "line 2");
  EXPECT_EQ(errorPlace("1\n" + indices("0") + "2\n0,0,0\n1,2,3\n"), "line 2");
}

TEST_F(BptFileErrors, WrongCounts) {
  EXPECT_EQ(errorPlace("2\n" + indices("2") + "5\n0,0,0\n0,0,0\n0,0,0\n0,0,0\n1,2,3\n"), "line 3");  // "5" read as indices
  EXPECT_EQ(errorPlace("1\n" + indices("2") + "3\n0,0,0\n1,2,3\n"), "line 6");      // EOF
  EXPECT_EQ(errorPlace("1\n" + indices("2") + "1\n0,0,0\n1,2,3\n"), "line 5");      // extra point
  EXPECT_EQ(errorPlace(""), "line 1");
}

}  // namespace
}  // namespace rayes
