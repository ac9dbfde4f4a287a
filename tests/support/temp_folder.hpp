#pragma once
/// Test support: a temporary folder named after the running gtest, removed at the end of the
/// test (kept when DF_KEEP_TEST_FILES is set, for looking at what a test wrote).
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace df::test {

class TempFolder {
  public:
    /// tag names the folder; by default the running test's name.
    explicit TempFolder(const std::string& tag = "") {
        static std::atomic<int> counter{0};
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        const std::string stem = !tag.empty() ? tag : info != nullptr ? info->name() : "x";
        const std::string name = "df_" + stem + "_" + std::to_string(::getpid()) + "_" +
                                 std::to_string(counter++);
        path_ = std::filesystem::temp_directory_path() / name;
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~TempFolder() {
        if (std::getenv("DF_KEEP_TEST_FILES") != nullptr) return;
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    TempFolder(const TempFolder&) = delete;
    TempFolder& operator=(const TempFolder&) = delete;

    const std::filesystem::path& path() const { return path_; }
    std::string str() const { return path_.string(); }
    std::string operator/(const std::string& relative) const { return (path_ / relative).string(); }

  private:
    std::filesystem::path path_;
};

}  // namespace df::test
