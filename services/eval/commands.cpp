// df_eval's single-purpose subcommands: ate, rpe, object, recon, seg, timing.
#include "commands.hpp"

#include <cstdio>
#include <sstream>

#include "core/log.hpp"
#include "eval/plots.hpp"
#include "eval/report.hpp"
#include "eval/timing.hpp"
#include "io/ply/ply.hpp"
#include "timing_recording.hpp"

namespace df::eval_cli {

namespace {

using nlohmann::json;

int fail(const Status& status) {
    log::error(status.message());
    return 1;
}

Result<eval::LoadedTrajectory> load(const std::string& file) {
    auto loaded = eval::load_trajectory(file);
    if (loaded) {
        for (const auto& w : loaded->warnings) log::warn(w);
    }
    return loaded;
}

/// Writes the JSON document if asked; returns the exit code.
int finish(const Outputs& out, const json& doc) {
    if (!out.json_file.empty()) {
        const Status s = eval::write_json(out.json_file, doc);
        if (!s) return fail(s);
        log::info("wrote ", out.json_file);
    }
    return 0;
}

/// "tx ty tz qx qy qz qw" (commas allowed); `flag` names the option in errors.
Result<Eigen::Isometry3d> parse_transform(const std::string& text, const std::string& flag) {
    std::string spaced = text;
    for (char& c : spaced) c = c == ',' ? ' ' : c;
    std::istringstream in(spaced);
    std::vector<double> v;
    for (double x; in >> x;) v.push_back(x);
    if (!in.eof() || v.size() != 7) {
        return error(StatusCode::kInvalidArgument,
                     flag + ": expected 7 numbers 'tx ty tz qx qy qz qw', got '" + text + "'");
    }
    io::StampedPose pose;
    pose.t = Eigen::Vector3d(v[0], v[1], v[2]);
    const Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);
    if (q.norm() < 1e-9) return error(StatusCode::kInvalidArgument, flag + ": zero quaternion");
    pose.q = q.normalized();
    return eval::to_isometry(pose);
}

}  // namespace

int cmd_ate(const std::string& gt_file, const std::string& est_file,
            const eval::AssociationConfig& config, const Outputs& out) {
    auto gt = load(gt_file);
    if (!gt) return fail(gt.status());
    auto est = load(est_file);
    if (!est) return fail(est.status());
    auto ate = eval::compute_ate(gt->poses, est->poses, config);
    if (!ate) return fail(ate.status().with_context("ATE of " + est_file + " against " + gt_file));
    std::fputs(eval::format_ate(*ate, "ATE: " + est_file + " vs " + gt_file).c_str(), stdout);
    if (!out.plot_file.empty()) {
        const Status s = eval::plot_ate(out.plot_file, *ate, gt->poses, est->poses, "ATE");
        if (!s) return fail(s);
        log::info("wrote ", out.plot_file);
    }
    return finish(out, {{"gt", gt_file}, {"est", est_file}, {"ate", eval::to_json(*ate)}});
}

int cmd_rpe(const std::string& gt_file, const std::string& est_file, const eval::RpeConfig& config,
            const Outputs& out) {
    auto gt = load(gt_file);
    if (!gt) return fail(gt.status());
    auto est = load(est_file);
    if (!est) return fail(est.status());
    auto rpe = eval::compute_rpe(gt->poses, est->poses, config);
    if (!rpe) return fail(rpe.status().with_context("RPE of " + est_file + " against " + gt_file));
    std::fputs(eval::format_rpe(*rpe, "RPE: " + est_file + " vs " + gt_file).c_str(), stdout);
    if (!out.plot_file.empty()) {
        const Status s = eval::plot_rpe(out.plot_file, *rpe, "RPE");
        if (!s) return fail(s);
        log::info("wrote ", out.plot_file);
    }
    return finish(out, {{"gt", gt_file}, {"est", est_file}, {"rpe", eval::to_json(*rpe)}});
}

int cmd_object(const std::string& gt_file, const std::string& est_file,
               const eval::AssociationConfig& association, const eval::RpeConfig& rpe,
               const ObjectOptions& options, const Outputs& out) {
    eval::ObjectAlignment alignment;
    alignment.object_frame = options.body_align;
    if (!options.world.empty()) {
        auto world = parse_transform(options.world, "--world");
        if (!world) return fail(world.status());
        alignment.world_gt_T_est = *world;
    }
    auto gt = load(gt_file);
    if (!gt) return fail(gt.status());
    auto est = load(est_file);
    if (!est) return fail(est.status());
    auto object = eval::compute_object_errors(gt->poses, est->poses, alignment, association, rpe);
    if (!object) {
        return fail(
            object.status().with_context("object trajectory " + est_file + " against " + gt_file));
    }
    std::fputs(eval::format_object(*object, "Object: " + est_file + " vs " + gt_file).c_str(),
               stdout);
    if (!out.plot_file.empty()) {
        const Status s = eval::plot_object(out.plot_file, *object, gt->poses, est->poses, "object");
        if (!s) return fail(s);
        log::info("wrote ", out.plot_file);
    }
    return finish(out, {{"gt", gt_file}, {"est", est_file}, {"object", eval::to_json(*object)}});
}

int cmd_recon(const std::string& gt_ply, const std::string& est_ply,
              const eval::ReconstructionConfig& config, const std::string& transform,
              const std::optional<eval::RegistrationConfig>& registration, const Outputs& out) {
    Eigen::Isometry3d gt_T_est = Eigen::Isometry3d::Identity();
    if (!transform.empty()) {
        auto parsed = parse_transform(transform, "--transform");
        if (!parsed) return fail(parsed.status());
        gt_T_est = *parsed;
    }
    io::PlyReadInfo gt_info, est_info;
    auto gt = io::read_ply(gt_ply, &gt_info);
    if (!gt) return fail(gt.status());
    auto est = io::read_ply(est_ply, &est_info);
    if (!est) return fail(est.status());
    for (const auto* info : {&gt_info, &est_info}) {
        if (info->skipped_nonfinite) {
            log::warn(info == &gt_info ? gt_ply : est_ply, ": skipped ", info->skipped_nonfinite,
                      " vertices with non-finite coordinates");
        }
    }
    auto recon = eval::score_reconstruction(
        gt->positions, eval::transform_points(gt_T_est, est->positions), config);
    if (!recon) return fail(recon.status().with_context(est_ply + " against " + gt_ply));
    std::fputs(
        eval::format_reconstruction(*recon, "Reconstruction: " + est_ply + " vs " + gt_ply).c_str(),
        stdout);
    json result = {{"gt", gt_ply}, {"est", est_ply}, {"reconstruction", eval::to_json(*recon)}};
    if (registration) {
        auto registered =
            eval::score_registered(gt->positions, est->positions, gt_T_est, config, *registration);
        if (!registered) return fail(registered.status().with_context(est_ply + " onto " + gt_ply));
        std::fputs(
            eval::format_reconstruction(
                registered->score, "After rigid registration onto the ground truth (" +
                                       eval::format_registration(registered->registration) + ")")
                .c_str(),
            stdout);
        result["registered"] = eval::to_json(registered->score);
        result["registered"]["registration"] = eval::to_json(registered->registration);
    }
    return finish(out, result);
}

int cmd_seg(const std::string& gt_sequence, const std::string& pred_dir,
            const eval::SegmentationConfig& config, const Outputs& out) {
    auto seg = eval::score_segmentation_folders(gt_sequence, pred_dir, config);
    if (!seg) return fail(seg.status());
    std::fputs(
        eval::format_segmentation(*seg, "Segmentation: " + pred_dir + " vs " + gt_sequence).c_str(),
        stdout);
    return finish(out,
                  {{"gt", gt_sequence}, {"pred", pred_dir}, {"segmentation", eval::to_json(*seg)}});
}

int cmd_mask(const std::string& gt_dir, const std::string& pred_dir, const Outputs& out) {
    auto score = eval::score_mask_folders(gt_dir, pred_dir);
    if (!score) return fail(score.status());
    std::printf(
        "Masks: %s vs %s\n  frames %d (%d with a mask, %d without a prediction)\n"
        "  IoU mean %.3f, pooled %.3f; precision %.3f, recall %.3f\n",
        pred_dir.c_str(), gt_dir.c_str(), score->frames, score->frames_with_gt, score->missing,
        score->mean_iou, score->pooled_iou, score->mean_precision, score->mean_recall);
    return finish(out, {{"gt", gt_dir},
                        {"pred", pred_dir},
                        {"mask",
                         {{"frames", score->frames},
                          {"frames_with_gt", score->frames_with_gt},
                          {"missing", score->missing},
                          {"mean_iou", score->mean_iou},
                          {"pooled_iou", score->pooled_iou},
                          {"mean_precision", score->mean_precision},
                          {"mean_recall", score->mean_recall}}}});
}

int cmd_timing(const std::vector<std::string>& logs, const Outputs& out) {
    std::vector<eval::TimingSample> samples;
    for (const std::string& file : logs) {
        if (is_mcap_file(file)) {  // a recording: the stages' StageStatus messages
            auto recorded = read_timing_recording(file);
            if (!recorded) return fail(recorded.status());
            samples.insert(samples.end(), recorded->begin(), recorded->end());
            continue;
        }
        auto log_file = eval::read_timing_log(file);
        if (!log_file) return fail(log_file.status());
        for (const auto& e : log_file->errors) log::warn(e);
        samples.insert(samples.end(), log_file->samples.begin(), log_file->samples.end());
    }
    const auto stats = eval::summarize_timing(samples);
    std::fputs(eval::format_timing(stats, "Timing (" + std::to_string(samples.size()) + " records)")
                   .c_str(),
               stdout);
    return finish(out, {{"logs", logs}, {"timing", eval::to_json(stats)}});
}

}  // namespace df::eval_cli
