// Per-test scratch folders: <temp>/ghr_<pid>_<suite>_<test>, made on first use and removed when the
// test ends, passed or failed (the listener in test_main.cpp), so no run leaves folders behind in the
// system's temporary directory. ctest runs tests in parallel processes: the pid keeps them apart.
#pragma once
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>

namespace testutil {

inline std::filesystem::path testDirFor(const ::testing::TestInfo& info) {
  std::string name = "ghr_" + std::to_string(::getpid()) + "_" + info.test_suite_name() + "_" + info.name();
  std::replace(name.begin(), name.end(), '/', '_');
  return std::filesystem::temp_directory_path() / name;
}

/// The running test's own folder (created if needed).
inline std::filesystem::path testDir() {
  std::filesystem::path p = testDirFor(*::testing::UnitTest::GetInstance()->current_test_info());
  std::filesystem::create_directories(p);
  return p;
}

/// Removes each test's folder when the test ends.
class TestDirCleaner : public ::testing::EmptyTestEventListener {
  void OnTestEnd(const ::testing::TestInfo& info) override {
    std::error_code ec;
    std::filesystem::remove_all(testDirFor(info), ec);
  }
};

}  // namespace testutil
