// Reading a sequence's instance ground truth and a folder of predicted masks.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "eval/segmentation.hpp"
#include "eval/trajectory_metrics.hpp"
#include "io/tum/trajectory.hpp"
#include "io/tum/tum_folder.hpp"

namespace df::eval {

namespace fs = std::filesystem;

namespace {

/// A path field of an instances.json entry: a string, null ("" = none) or absent (the default).
Status read_path(const nlohmann::json& entry, const char* key, const std::string& fallback,
                 const std::string& where, std::string* path) {
    if (!entry.contains(key)) {
        *path = fallback;
    } else if (entry[key].is_null()) {
        path->clear();
    } else if (entry[key].is_string()) {
        *path = entry[key].get<std::string>();
    } else {
        return error(StatusCode::kInvalidArgument,
                     where + "\"" + key + "\" must be a path (string) or null");
    }
    return Status::ok();
}

}  // namespace

Result<std::vector<GtInstance>> read_instances_json(const std::string& file) {
    std::ifstream in(file);
    if (!in) return error(StatusCode::kNotFound, file + ": cannot open instances file");
    nlohmann::json doc;
    try {
        doc = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
        return error(StatusCode::kInvalidArgument, file + ": not valid JSON: " + e.what());
    }
    if (!doc.is_object() || !doc.contains("instances") || !doc["instances"].is_array()) {
        return error(StatusCode::kInvalidArgument,
                     file + ": expected an object with an array \"instances\"");
    }
    std::vector<GtInstance> instances;
    for (size_t i = 0; i < doc["instances"].size(); ++i) {
        const nlohmann::json& e = doc["instances"][i];
        const std::string where = file + ": instances[" + std::to_string(i) + "]: ";
        if (!e.is_object() || !e.contains("id") || !e["id"].is_number_integer()) {
            return error(StatusCode::kInvalidArgument, where + "expected an integer \"id\"");
        }
        GtInstance inst;
        inst.id = e["id"].get<int>();
        if (inst.id < 1 || inst.id > 65535) {
            return error(StatusCode::kInvalidArgument,
                         where + "id " + std::to_string(inst.id) + " is outside 1..65535");
        }
        inst.name = e.value("name", "id" + std::to_string(inst.id));
        inst.class_name = e.value("class_name", std::string());
        if (e.contains("class_id") && e["class_id"].is_number_integer()) {
            inst.class_id = e["class_id"].get<int>();
        }
        DF_RETURN_IF_ERROR(
            read_path(e, "model", "models/" + inst.name + ".ply", where, &inst.model));
        DF_RETURN_IF_ERROR(
            read_path(e, "trajectory", "objects/" + inst.name + ".txt", where, &inst.trajectory));
        const std::string kind = e.value("kind", std::string("unknown"));
        if (kind == "rigid") {
            inst.kind = InstanceKind::kRigid;
        } else if (kind == "non_rigid") {
            inst.kind = InstanceKind::kNonRigid;
        } else if (kind == "unknown") {
            inst.kind = InstanceKind::kUnknown;
        } else {
            return error(StatusCode::kInvalidArgument,
                         where + "kind '" + kind + "' is not rigid, non_rigid or unknown");
        }
        for (const GtInstance& other : instances) {
            if (other.id == inst.id) {
                return error(StatusCode::kInvalidArgument,
                             where + "id " + std::to_string(inst.id) + " is listed twice");
            }
        }
        instances.push_back(inst);
    }
    return instances;
}

namespace {

struct StampedFile {
    double stamp_s;
    std::string path;
};

/// The *.png files of a folder whose names are stamps, sorted by stamp.
Result<std::vector<StampedFile>> list_stamped_pngs(const std::string& dir) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) {
        return error(StatusCode::kNotFound, dir + ": no such folder");
    }
    std::vector<StampedFile> files;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
        if (entry.path().extension() != ".png") continue;
        double stamp = 0;
        if (!io::parse_tum_stamp(entry.path().stem().string(), &stamp)) {
            return error(StatusCode::kInvalidArgument,
                         entry.path().string() + ": expected a file named <stamp>.png");
        }
        files.push_back({stamp, entry.path().string()});
    }
    if (ec) return error(StatusCode::kIoError, dir + ": cannot list: " + ec.message());
    std::sort(files.begin(), files.end(),
              [](const StampedFile& a, const StampedFile& b) { return a.stamp_s < b.stamp_s; });
    return files;
}

}  // namespace

Result<cv::Mat> read_label_png(const std::string& file) {
    cv::Mat image;
    try {
        image = cv::imread(file, cv::IMREAD_UNCHANGED);
    } catch (const cv::Exception& e) {
        return error(StatusCode::kIoError, file + ": cannot read: " + e.what());
    }
    if (image.empty()) return error(StatusCode::kIoError, file + ": cannot read image");
    return image;
}

Result<SegmentationResult> score_segmentation_folders(const std::string& gt_sequence_dir,
                                                      const std::string& pred_dir,
                                                      const SegmentationConfig& config) {
    auto instances = read_instances_json((fs::path(gt_sequence_dir) / "instances.json").string());
    if (!instances) return instances.status();
    auto gt_files = list_stamped_pngs((fs::path(gt_sequence_dir) / "instances").string());
    if (!gt_files) return gt_files.status();
    if (gt_files->empty()) {
        return error(StatusCode::kNotFound,
                     gt_sequence_dir + "/instances: no ground-truth <stamp>.png files");
    }
    auto pred_files = list_stamped_pngs(pred_dir);
    if (!pred_files) return pred_files.status();
    std::vector<double> gt_stamps, pred_stamps;
    for (const auto& f : *gt_files) gt_stamps.push_back(f.stamp_s);
    for (const auto& f : *pred_files) pred_stamps.push_back(f.stamp_s);
    const auto matches =
        associate_stamps(gt_stamps, pred_stamps, {config.max_stamp_difference_s, 0.0});
    std::vector<int> pred_of_gt(gt_files->size(), -1);
    for (const StampMatch& m : matches) pred_of_gt[m.gt] = static_cast<int>(m.est);

    // With moving_min_m: per instance, whether it moved since the previous GT frame.
    std::vector<std::vector<bool>> still(instances->size());
    if (config.moving_min_m > 0) {
        for (size_t k = 0; k < instances->size(); ++k) {
            const GtInstance& inst = (*instances)[k];
            still[k].assign(gt_files->size(), true);
            if (inst.trajectory.empty()) continue;
            const std::string file = (fs::path(gt_sequence_dir) / inst.trajectory).string();
            auto poses = io::read_tum_trajectory(file);
            if (!poses) return poses.status();
            std::vector<double> stamps;
            for (const io::StampedPose& p : poses->poses) stamps.push_back(p.stamp_s);
            const auto pairs = associate_stamps(gt_stamps, stamps, {1e-3, 0.0});
            std::vector<int> pose_of_gt(gt_files->size(), -1);
            for (const StampMatch& m : pairs) pose_of_gt[m.gt] = static_cast<int>(m.est);
            for (size_t i = 1; i < gt_files->size(); ++i) {
                if (pose_of_gt[i] < 0 || pose_of_gt[i - 1] < 0) continue;
                const double moved = (poses->poses[static_cast<size_t>(pose_of_gt[i])].t -
                                      poses->poses[static_cast<size_t>(pose_of_gt[i - 1])].t)
                                         .norm();
                still[k][i] = moved < config.moving_min_m;
            }
        }
    }
    SegmentationScorer scorer(*instances, config);
    for (size_t i = 0; i < gt_files->size(); ++i) {
        auto gt = read_label_png((*gt_files)[i].path);
        if (!gt) return gt.status();
        if (config.moving_min_m > 0) {
            for (size_t k = 0; k < instances->size(); ++k)
                if (still[k][i]) gt->setTo(0, *gt == (*instances)[k].id);
        }
        cv::Mat pred;
        if (pred_of_gt[i] >= 0) {
            const std::string& pred_file = (*pred_files)[static_cast<size_t>(pred_of_gt[i])].path;
            auto read = read_label_png(pred_file);
            if (!read) return read.status();
            pred = *read;
            DF_RETURN_IF_ERROR(scorer.add_frame(
                *gt, pred, (*gt_files)[i].path + " (prediction " + pred_file + ")"));
        } else {
            scorer.add_missing_frame();
            if (!config.skip_missing) {
                DF_RETURN_IF_ERROR(scorer.add_frame(*gt, pred, (*gt_files)[i].path));
            }
        }
        if (config.progress) {
            config.progress(static_cast<int>(i + 1), static_cast<int>(gt_files->size()));
        }
    }
    for (size_t k = matches.size(); k < pred_files->size(); ++k) scorer.add_unpaired_prediction();
    return scorer.result();
}

}  // namespace df::eval

namespace df::eval {

Result<MaskScore> score_mask_folders(const std::string& gt_dir, const std::string& pred_dir) {
    std::error_code ec;
    if (!fs::is_directory(gt_dir, ec))
        return error(StatusCode::kNotFound, "ground-truth mask folder '" + gt_dir + "' not found");
    if (!fs::is_directory(pred_dir, ec))
        return error(StatusCode::kNotFound, "predicted mask folder '" + pred_dir + "' not found");
    std::vector<fs::path> files;
    for (const fs::directory_entry& e : fs::directory_iterator(gt_dir, ec))
        if (e.is_regular_file() && e.path().extension() == ".png") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    if (files.empty()) return error(StatusCode::kNotFound, "no .png masks in '" + gt_dir + "'");
    MaskScore score;
    double inter_sum = 0, union_sum = 0;
    for (const fs::path& file : files) {
        auto gt = read_label_png(file.string());
        if (!gt) return gt.status();
        ++score.frames;
        const cv::Mat truth = *gt != 0;
        cv::Mat pred = cv::Mat::zeros(truth.size(), CV_8UC1);
        const fs::path pred_file = fs::path(pred_dir) / file.filename();
        if (fs::exists(pred_file, ec)) {
            auto p = read_label_png(pred_file.string());
            if (!p) return p.status();
            cv::Mat m = *p != 0;
            if (m.size() != truth.size()) cv::resize(m, m, truth.size(), 0, 0, cv::INTER_NEAREST);
            pred = m;
        } else {
            ++score.missing;
        }
        const double t = cv::countNonZero(truth);
        if (t == 0) continue;
        const double p = cv::countNonZero(pred);
        const double i = cv::countNonZero(truth & pred);
        const double u = t + p - i;
        ++score.frames_with_gt;
        score.mean_iou += i / u;
        score.mean_precision += p > 0 ? i / p : 0.0;
        score.mean_recall += i / t;
        inter_sum += i;
        union_sum += u;
    }
    if (score.frames_with_gt > 0) {
        score.mean_iou /= score.frames_with_gt;
        score.mean_precision /= score.frames_with_gt;
        score.mean_recall /= score.frames_with_gt;
        score.pooled_iou = inter_sum / union_sum;
    }
    return score;
}

}  // namespace df::eval
