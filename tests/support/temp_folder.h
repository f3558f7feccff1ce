// The one temporary-folder helper of the tests: an empty folder named after the process and the
// running test (so parallel test programs never share one), removed with its content when the
// helper goes out of scope. Use it as a fixture member or a local in a TEST.
#pragma once
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>
#include <unistd.h>
#include <gtest/gtest.h>

namespace rayes::testing {

class TempFolder {
 public:
  TempFolder() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = info ? std::string(info->test_suite_name()) + "-" + info->name() : "no-test";
    std::replace(name.begin(), name.end(), '/', '_');
    static int made = 0;  // two folders in one test must not share a name
    dir_ = std::filesystem::temp_directory_path() /
           ("rayes-" + std::to_string(::getpid()) + "-" + std::to_string(made++) + "-" + name);
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  ~TempFolder() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;

  const std::filesystem::path& dir() const { return dir_; }
  // The path of `name` inside the folder.
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  // Writes `content` (bytes, as given) to `name`, creating folders on the way; returns the path.
  std::string write(const std::string& name, const std::string& content) const {
    const auto p = dir_ / name;
    std::filesystem::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << content;
    return p.string();
  }
  // The bytes of `name` ("" when it cannot be read).
  std::string read(const std::string& name) const {
    std::ifstream in(dir_ / name, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }
  // Every path inside the folder (recursively, relative, sorted), to check what a run left.
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir_))
      names.push_back(std::filesystem::relative(e.path(), dir_).string());
    std::sort(names.begin(), names.end());
    return names;
  }

 private:
  std::filesystem::path dir_;
};

}  // namespace rayes::testing
