// Loading trajectories for scoring, and the stamp association of TUM's associate.py.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "eval/trajectory_metrics.hpp"

namespace df::eval {

Result<LoadedTrajectory> load_trajectory(const std::string& file) {
    auto parse = io::read_tum_trajectory(file);
    if (!parse) return parse.status();
    if (!parse->errors.empty()) {
        std::string message = parse->errors.front();
        if (parse->errors.size() > 1) {
            message += " (and " + std::to_string(parse->errors.size() - 1) + " more bad lines)";
        }
        return error(StatusCode::kInvalidArgument, message);
    }
    if (parse->poses.empty()) {
        return error(StatusCode::kInvalidArgument,
                     file + ": no poses (expected lines 'timestamp tx ty tz qx qy qz qw')");
    }
    LoadedTrajectory loaded;
    loaded.file = file;
    loaded.poses = std::move(parse->poses);
    const size_t dropped = sort_unique_by_stamp(&loaded.poses);
    if (dropped > 0) {
        loaded.warnings.push_back(file + ": " + std::to_string(dropped) +
                                  " stamps appear more than once; the last line of each is used");
    }
    return loaded;
}

size_t sort_unique_by_stamp(Trajectory* trajectory) {
    Trajectory& t = *trajectory;
    std::stable_sort(t.begin(), t.end(), [](const io::StampedPose& a, const io::StampedPose& b) {
        return a.stamp_s < b.stamp_s;
    });
    Trajectory unique;
    unique.reserve(t.size());
    for (size_t i = 0; i < t.size(); ++i) {
        // Of a run of equal stamps keep the last (a dict keeps the last assignment).
        if (i + 1 < t.size() && t[i + 1].stamp_s == t[i].stamp_s) continue;
        unique.push_back(t[i]);
    }
    const size_t dropped = t.size() - unique.size();
    t = std::move(unique);
    return dropped;
}

std::vector<double> stamps_of(const Trajectory& trajectory) {
    std::vector<double> stamps;
    stamps.reserve(trajectory.size());
    for (const auto& p : trajectory) stamps.push_back(p.stamp_s);
    return stamps;
}

std::vector<StampMatch> associate_stamps(const std::vector<double>& gt_stamps_s,
                                         const std::vector<double>& est_stamps_s,
                                         const AssociationConfig& config) {
    struct Candidate {
        double diff;
        size_t gt, est;
    };
    std::vector<Candidate> candidates;
    const double window = config.max_difference_s;
    for (size_t g = 0; g < gt_stamps_s.size(); ++g) {
        const double a = gt_stamps_s[g];
        // Candidates lie where est + offset is within the window of a; search a little wider and
        // let the exact test below (TUM's expression) decide.
        const double lo = a - config.offset_s - window - 1e-9 * (std::abs(a) + 1);
        auto it = std::lower_bound(est_stamps_s.begin(), est_stamps_s.end(), lo);
        for (; it != est_stamps_s.end(); ++it) {
            const double b = *it;
            const double diff = std::abs(a - (b + config.offset_s));
            if (diff < window) {
                candidates.push_back({diff, g, static_cast<size_t>(it - est_stamps_s.begin())});
            } else if (b + config.offset_s > a) {
                break;
            }
        }
    }
    // Stamps are sorted and unique, so ordering by index equals TUM's ordering by stamp.
    std::sort(candidates.begin(), candidates.end(), [](const Candidate& x, const Candidate& y) {
        if (x.diff != y.diff) return x.diff < y.diff;
        if (x.gt != y.gt) return x.gt < y.gt;
        return x.est < y.est;
    });
    std::vector<bool> gt_used(gt_stamps_s.size(), false), est_used(est_stamps_s.size(), false);
    std::vector<StampMatch> matches;
    for (const Candidate& c : candidates) {
        if (gt_used[c.gt] || est_used[c.est]) continue;
        gt_used[c.gt] = est_used[c.est] = true;
        matches.push_back({c.gt, c.est});
    }
    std::sort(matches.begin(), matches.end(),
              [](const StampMatch& x, const StampMatch& y) { return x.gt < y.gt; });
    return matches;
}

std::string describe_ranges(const Trajectory& gt, const Trajectory& est) {
    auto range = [](const Trajectory& t) {
        if (t.empty()) return std::string("no poses");
        char text[128];
        std::snprintf(text, sizeof text, "%zu poses in [%.6f, %.6f] s", t.size(), t.front().stamp_s,
                      t.back().stamp_s);
        return std::string(text);
    };
    return "ground truth has " + range(gt) + ", estimate has " + range(est);
}

std::string describe_no_overlap(const Trajectory& gt, const Trajectory& est,
                                const AssociationConfig& config, size_t pairs_found) {
    char tail[160];
    std::snprintf(tail, sizeof tail,
                  " (pairs need |t_gt - (t_est + %g)| < %g s; found %zu, need at least 2)",
                  config.offset_s, config.max_difference_s, pairs_found);
    return "no common stamps: " + describe_ranges(gt, est) + tail;
}

Eigen::Isometry3d to_isometry(const io::StampedPose& pose) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = pose.q.normalized().toRotationMatrix();
    T.translation() = pose.t;
    return T;
}

const char* to_string(AlignmentKind kind) {
    switch (kind) {
        case AlignmentKind::kHornPositions:
            return "horn_positions";
        case AlignmentKind::kFirstPose:
            return "first_pose";
        case AlignmentKind::kGivenWorld:
            return "given_world";
        case AlignmentKind::kWorldAndObjectFirstPose:
            return "world_and_object_first_pose";
    }
    return "first_pose";
}
const char* to_string(DeltaUnit unit) { return unit == DeltaUnit::kSeconds ? "s" : "f"; }
const char* to_string(RpeForm form) { return form == RpeForm::kTumScript ? "tum" : "paper"; }

}  // namespace df::eval
