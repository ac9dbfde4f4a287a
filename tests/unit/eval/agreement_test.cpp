// df_eval ate/rpe against an independent numpy implementation of the TUM definitions
// (tum_reference.py), on random trajectories with gaps, stamp jitter, drift and a time offset.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "eval_test_support.hpp"
#include "io/tum/trajectory.hpp"

namespace df::eval {
namespace {

using nlohmann::json;
using test::run_command;
using test::TempFolder;

constexpr double kTolerance = 1e-6;  // metres, degrees

struct Case {
    const char* name;
    unsigned seed;
    double gt_rate_hz;
    double est_shift_s;  ///< added to the estimate's stamps (the CLI gets --offset -shift)
    double max_dt_s;
    double jitter_s;  ///< uniform +- on estimate stamps
    const char* form;
};

/// Writes gt.txt and est.txt of a case into `dir`.
void make_case(const Case& c, const TempFolder& dir) {
    std::mt19937 rng(c.seed);
    std::uniform_real_distribution<double> uni(-1, 1);
    std::normal_distribution<double> gauss(0, 1);
    auto in_gap = [](double t, std::initializer_list<std::pair<double, double>> gaps) {
        for (const auto& g : gaps) {
            if (t >= g.first && t < g.second) return true;
        }
        return false;
    };
    Trajectory gt, est;
    for (int i = 0; i < 20 * c.gt_rate_hz; ++i) {
        const double t = 100.0 + i / c.gt_rate_hz + 0.001 * uni(rng);
        if (in_gap(t, {{105.0, 105.6}, {112.0, 112.3}})) continue;
        gt.push_back(test::smooth_pose(std::round(t * 1e6) / 1e6));
    }
    const Eigen::Isometry3d est_T_gt = test::make_transform(
        0.9, Eigen::Vector3d(uni(rng), uni(rng), 1), Eigen::Vector3d(uni(rng), 2, uni(rng)));
    for (int i = 0; i < 20 * 30; ++i) {
        const double t = 100.013 + i / 30.0;
        if (in_gap(t, {{108.0, 109.0}})) continue;
        io::StampedPose p = test::smooth_pose(t);
        const double since = t - 100.0;
        // Drift (1 cm/s, 0.5 deg/s) and noise (1 cm, 0.5 deg): the RPE forms differ.
        p.t +=
            Eigen::Vector3d(0.01 * since + 0.01 * gauss(rng), 0.01 * gauss(rng), 0.01 * gauss(rng));
        const Eigen::Vector3d axis(gauss(rng), gauss(rng), gauss(rng));
        p.q = p.q * Eigen::Quaterniond(Eigen::AngleAxisd(
                        (0.5 * since + 0.5 * gauss(rng)) / kDegPerRad, axis.normalized()));
        p = test::transformed(est_T_gt, p);
        p.stamp_s = std::round((t + c.est_shift_s + c.jitter_s * uni(rng)) * 1e6) / 1e6;
        est.push_back(p);
    }
    // A stamp given twice: both tools keep the later line.
    io::StampedPose dup = est[100];
    dup.t.x() += 0.5;
    est.insert(est.begin() + 101, dup);
    ASSERT_TRUE(io::write_tum_trajectory(dir / "gt.txt", gt));
    ASSERT_TRUE(io::write_tum_trajectory(dir / "est.txt", est));
}

double max_stats_difference(const json& a, const json& b, const char* what) {
    double worst = 0;
    for (const char* key : {"rmse", "mean", "median", "std", "min", "max"}) {
        const double d = std::abs(a.at(key).get<double>() - b.at(key).get<double>());
        EXPECT_LT(d, kTolerance) << what << "." << key;
        worst = std::max(worst, d);
    }
    EXPECT_EQ(a.at("count"), b.at("count")) << what;
    return worst;
}

bool python_has_numpy() {
    std::string out;
    return run_command(std::string(DF_PYTHON) + " -c 'import numpy'", &out) == 0;
}

class Agreement : public ::testing::TestWithParam<Case> {};

TEST_P(Agreement, DfEvalMatchesTheNumpyReference) {
    if (!python_has_numpy()) GTEST_SKIP() << DF_PYTHON << " has no numpy";
    const Case& c = GetParam();
    TempFolder dir;
    make_case(c, dir);
    if (const char* keep = std::getenv("DF_EVAL_AGREEMENT_DIR")) {  // to rerun other tools on them
        const std::filesystem::path kept = std::filesystem::path(keep) / c.name;
        std::filesystem::create_directories(kept);
        for (const char* f : {"gt.txt", "est.txt"}) {
            std::filesystem::copy_file(dir / f, kept / f,
                                       std::filesystem::copy_options::overwrite_existing);
        }
    }
    char opts[128];
    std::snprintf(opts, sizeof opts, " --max-dt %.17g --offset %.17g", c.max_dt_s, -c.est_shift_s);
    const std::string files = " " + dir / "gt.txt" + " " + dir / "est.txt";
    std::string out;
    ASSERT_EQ(
        run_command(
            std::string(DF_EVAL_BIN) + " ate" + files + opts + " --json " + dir / "ate.json", &out),
        0)
        << out;
    for (const char* unit : {"s", "f"}) {
        ASSERT_EQ(
            run_command(std::string(DF_EVAL_BIN) + " rpe" + files + " --unit " + unit + " --form " +
                            c.form + " --offset " + std::to_string(-c.est_shift_s) + " --json " +
                            dir / (std::string("rpe_") + unit + ".json"),
                        &out),
            0)
            << out;
    }
    ASSERT_EQ(run_command(std::string(DF_PYTHON) + " " + DF_TUM_REFERENCE + files + opts +
                              " --form " + c.form + " > " + dir / "ref.json",
                          &out),
              0)
        << out;
    const json ref = test::read_json(dir / "ref.json");
    const json ate = test::read_json(dir / "ate.json")["ate"];
    ASSERT_TRUE(ref.is_object() && ate.is_object());

    EXPECT_EQ(ate["pairs"], ref["ate"]["pairs"]);
    const double d_ate =
        max_stats_difference(ate["translation_m"], ref["ate"]["translation_m"], "ate");
    double d_align = 0;
    for (int r = 0; r < 4; ++r) {
        for (int k = 0; k < 4; ++k) {
            d_align = std::max(
                d_align, std::abs(ate["alignment_gt_T_est"]["matrix"][r][k].get<double>() -
                                  ref["ate"]["alignment_gt_T_est"]["matrix"][r][k].get<double>()));
        }
    }
    EXPECT_LT(d_align, kTolerance);
    double d_rpe_t = 0, d_rpe_r = 0;
    for (const char* unit : {"s", "f"}) {
        const json rpe = test::read_json(dir / (std::string("rpe_") + unit + ".json"))["rpe"];
        const json& expected = ref[std::string("rpe_") + unit];
        ASSERT_TRUE(rpe.is_object()) << unit;
        EXPECT_EQ(rpe["pairs"], expected["pairs"]) << unit;
        d_rpe_t = std::max(
            d_rpe_t, max_stats_difference(rpe["translation_m"], expected["translation_m"], unit));
        d_rpe_r = std::max(
            d_rpe_r, max_stats_difference(rpe["rotation_deg"], expected["rotation_deg"], unit));
    }
    std::printf(
        "agreement %s: %d ATE pairs, ATE rmse %.6f m; max |difference| ATE %.1e m, "
        "alignment %.1e, RPE translation %.1e m, RPE rotation %.1e deg\n",
        c.name, ate["pairs"].get<int>(), ate["translation_m"]["rmse"].get<double>(), d_ate, d_align,
        d_rpe_t, d_rpe_r);
}

INSTANTIATE_TEST_SUITE_P(
    Cases, Agreement,
    ::testing::Values(Case{"gaps_jitter", 1, 100.0, 0.0, 0.02, 0.008, "tum"},
                      Case{"paper_form", 2, 100.0, 0.0, 0.02, 0.008, "paper"},
                      Case{"time_offset", 3, 100.0, 0.3, 0.02, 0.005, "tum"},
                      Case{"same_rate_wide_window", 4, 30.0, 0.0, 0.05, 0.015, "tum"}),
    [](const ::testing::TestParamInfo<Case>& param) { return std::string(param.param.name); });

}  // namespace
}  // namespace df::eval
