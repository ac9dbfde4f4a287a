// df_eval mask: a folder of binary masks against ground-truth masks, by file name.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "eval/segmentation.hpp"

namespace df::eval {
namespace {

std::string fresh(const std::string& name) {
    const auto p = std::filesystem::temp_directory_path() /
                   ("df_mask_score_" + name + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(p);
    std::filesystem::create_directories(p);
    return p.string();
}

TEST(MaskScore, IoUPrecisionAndRecallOfKnownOverlaps) {
    const std::string gt = fresh("gt"), pred = fresh("pred");
    // Frame a: truth 20x10 = 200 px, prediction the left half of it plus 100 px outside.
    cv::Mat t = cv::Mat::zeros(40, 60, CV_8UC1), p = cv::Mat::zeros(40, 60, CV_16UC1);
    t(cv::Rect(10, 10, 20, 10)).setTo(255);
    p(cv::Rect(10, 10, 10, 10)).setTo(3);
    p(cv::Rect(40, 30, 10, 10)).setTo(7);
    ASSERT_TRUE(cv::imwrite(gt + "/a.png", t));
    ASSERT_TRUE(cv::imwrite(pred + "/a.png", p));
    // Frame b: truth empty (not scored); frame c: truth without a prediction (IoU 0).
    ASSERT_TRUE(cv::imwrite(gt + "/b.png", cv::Mat::zeros(40, 60, CV_8UC1)));
    ASSERT_TRUE(cv::imwrite(gt + "/c.png", t));
    auto s = score_mask_folders(gt, pred);
    ASSERT_TRUE(s.is_ok()) << s.status().message();
    EXPECT_EQ(s->frames, 3);
    EXPECT_EQ(s->frames_with_gt, 2);
    EXPECT_EQ(s->missing, 2);
    // a: intersection 100, union 200 + 200 - 100 = 300; c: 0.
    EXPECT_NEAR(s->mean_iou, (100.0 / 300.0 + 0.0) / 2, 1e-9);
    EXPECT_NEAR(s->pooled_iou, 100.0 / (300.0 + 200.0), 1e-9);
    EXPECT_NEAR(s->mean_precision, (0.5 + 0.0) / 2, 1e-9);
    EXPECT_NEAR(s->mean_recall, (0.5 + 0.0) / 2, 1e-9);
    std::filesystem::remove_all(gt);
    std::filesystem::remove_all(pred);
}

TEST(MaskScore, AMissingFolderIsNamed) {
    auto s = score_mask_folders("/nonexistent/masks", "/tmp");
    ASSERT_FALSE(s.is_ok());
    EXPECT_NE(s.status().message().find("/nonexistent/masks"), std::string::npos);
}

}  // namespace
}  // namespace df::eval
