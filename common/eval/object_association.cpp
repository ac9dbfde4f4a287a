// Associating estimated objects with ground-truth instances by mask overlap over all frames.
#include "eval/object_association.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <set>
#include <unordered_map>

namespace df::eval {

namespace {

namespace fs = std::filesystem;

/// Pixel counts of one frame by key est << 16 | gt (the all-zero key left out).
template <typename EstT>
std::unordered_map<uint32_t, size_t> count_frame(const cv::Mat& est, const cv::Mat& gt) {
    std::unordered_map<uint32_t, size_t> joint;
    for (int r = 0; r < gt.rows; ++r) {
        const uint16_t* g = gt.ptr<uint16_t>(r);
        const EstT* e = est.empty() ? nullptr : est.ptr<EstT>(r);
        uint32_t run_key = 0;
        size_t run = 0;
        for (int c = 0; c < gt.cols; ++c) {
            const uint32_t key = ((e ? uint32_t{e[c]} : 0u) << 16) | uint32_t{g[c]};
            if (run > 0 && key != run_key) {  // label images come in runs: count them at once
                if (run_key != 0) joint[run_key] += run;
                run = 0;
            }
            run_key = key;
            ++run;
        }
        if (run > 0 && run_key != 0) joint[run_key] += run;
    }
    return joint;
}

std::string percent(double fraction) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f%%", 100.0 * fraction);
    return text;
}

ObjectPair make_pair(const MaskOverlap& overlap, int est_id, int gt_id) {
    ObjectPair p;
    p.est_id = est_id;
    p.gt_id = gt_id;
    const auto pair = overlap.pairs().find({est_id, gt_id});
    if (pair != overlap.pairs().end()) {
        p.intersection_px = pair->second.intersection_px;
        p.frames = pair->second.frames;
    }
    const auto e = overlap.estimated().find(est_id);
    const auto g = overlap.ground_truth().find(gt_id);
    p.est_px = e == overlap.estimated().end() ? 0 : e->second.pixels;
    p.gt_px = g == overlap.ground_truth().end() ? 0 : g->second.pixels;
    const double i = static_cast<double>(p.intersection_px);
    p.overlap = p.est_px ? i / static_cast<double>(p.est_px) : 0.0;
    const size_t union_px = p.est_px + p.gt_px - p.intersection_px;
    p.iou = union_px ? i / static_cast<double>(union_px) : 0.0;
    return p;
}

/// The instance sharing the most pixels with est_id (ties: the lower id); 0 if none.
int best_instance(const MaskOverlap& overlap, int est_id) {
    int best = 0;
    size_t best_px = 0;
    for (auto it = overlap.pairs().lower_bound({est_id, 0});
         it != overlap.pairs().end() && it->first.first == est_id; ++it) {
        if (it->second.intersection_px > best_px) {
            best = it->first.second;
            best_px = it->second.intersection_px;
        }
    }
    return best;
}

/// The *.png files of a folder by file name; kNotFound if there is no such folder.
Result<std::map<std::string, std::string>> pngs_by_name(const fs::path& dir) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) {
        return error(StatusCode::kNotFound, dir.string() + ": no such folder");
    }
    std::map<std::string, std::string> files;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
        if (entry.path().extension() == ".png") {
            files[entry.path().filename().string()] = entry.path().string();
        }
    }
    if (ec) return error(StatusCode::kIoError, dir.string() + ": cannot list: " + ec.message());
    return files;
}

}  // namespace

Status MaskOverlap::add_frame(const cv::Mat& est, const cv::Mat& gt, const std::string& frame) {
    if (gt.type() != CV_16UC1) {
        return error(StatusCode::kInvalidArgument,
                     frame + ": ground-truth instance image must be 16-bit, one channel");
    }
    if (!est.empty() && est.type() != CV_16UC1 && est.type() != CV_8UC1) {
        return error(StatusCode::kInvalidArgument,
                     frame + ": object mask must be 16-bit (or 8-bit), one channel");
    }
    if (!est.empty() && est.size() != gt.size()) {
        return error(StatusCode::kInvalidArgument,
                     frame + ": object mask is " + std::to_string(est.cols) + "x" +
                         std::to_string(est.rows) + ", ground truth " + std::to_string(gt.cols) +
                         "x" + std::to_string(gt.rows));
    }
    const auto joint =
        est.type() == CV_8UC1 ? count_frame<uint8_t>(est, gt) : count_frame<uint16_t>(est, gt);
    std::map<int, size_t> est_px, gt_px;
    for (const auto& [key, n] : joint) {
        const int e = static_cast<int>(key >> 16), g = static_cast<int>(key & 0xffff);
        if (e) est_px[e] += n;
        if (g) gt_px[g] += n;
        if (e && g) pairs_[{e, g}].intersection_px += n;
    }
    for (const auto& [id, n] : est_px) {
        est_[id].pixels += n;
        ++est_[id].frames;
        for (const auto& g : gt_px) ++pairs_[{id, g.first}].frames;
    }
    for (const auto& [id, n] : gt_px) {
        gt_[id].pixels += n;
        ++gt_[id].frames;
    }
    ++frames_;
    return Status::ok();
}

ObjectAssociation associate_objects(const MaskOverlap& overlap,
                                    const std::vector<GtInstance>& instances,
                                    const std::vector<int>& est_ids,
                                    const ObjectAssociationConfig& config) {
    ObjectAssociation result;
    result.config = config;
    result.frames = overlap.frames();
    std::map<int, const GtInstance*> by_id;
    for (const GtInstance& inst : instances) by_id[inst.id] = &inst;
    std::set<int> ids(est_ids.begin(), est_ids.end());
    for (const auto& e : overlap.estimated()) ids.insert(e.first);

    std::vector<ObjectPair> candidates;
    for (int id : ids) {
        SpuriousObject s;
        s.est_id = id;
        s.best_gt_id = best_instance(overlap, id);
        const ObjectPair p = make_pair(overlap, id, s.best_gt_id);
        s.est_px = p.est_px;
        s.overlap = p.overlap;
        const auto inst = by_id.find(s.best_gt_id);
        if (p.est_px == 0) {
            s.reason = "claimed no pixel";
        } else if (s.best_gt_id == 0) {
            s.reason = "shares no pixel with an instance";
        } else if (inst == by_id.end()) {
            s.reason = "on instance id " + std::to_string(s.best_gt_id) + ", not in instances.json";
        } else if (p.overlap < config.min_overlap) {
            s.reason = "best " + percent(p.overlap) + " of its pixels on " + inst->second->name +
                       " (needs " + percent(config.min_overlap) + ")";
        } else if (inst->second->kind != InstanceKind::kRigid) {
            s.reason = "on " + inst->second->name + ", kind " + to_string(inst->second->kind) +
                       ", not rigid";
        } else {
            candidates.push_back(p);
            continue;
        }
        result.spurious.push_back(s);
    }
    std::sort(candidates.begin(), candidates.end(), [](const ObjectPair& a, const ObjectPair& b) {
        return a.intersection_px != b.intersection_px ? a.intersection_px > b.intersection_px
                                                      : a.est_id < b.est_id;
    });
    std::set<int> taken;
    for (const ObjectPair& p : candidates) {
        (taken.insert(p.gt_id).second ? result.matches : result.duplicates).push_back(p);
    }
    std::sort(result.matches.begin(), result.matches.end(),
              [](const ObjectPair& a, const ObjectPair& b) { return a.gt_id < b.gt_id; });
    for (const GtInstance& inst : instances) {
        if (inst.kind != InstanceKind::kRigid || taken.count(inst.id)) continue;
        const auto g = overlap.ground_truth().find(inst.id);
        const size_t frames = g == overlap.ground_truth().end() ? 0 : g->second.frames;
        (frames >= config.min_frames ? result.missed : result.not_expected).push_back(inst.id);
    }
    return result;
}

Result<MaskFolderOverlap> accumulate_mask_folders(const std::string& sequence_dir,
                                                  const std::string& run_dir) {
    MaskFolderOverlap out;
    auto instances = read_instances_json((fs::path(sequence_dir) / "instances.json").string());
    if (!instances) return instances.status();
    out.instances = std::move(*instances);
    std::set<int> known;
    for (const GtInstance& inst : out.instances) known.insert(inst.id);
    auto gt_files = pngs_by_name(fs::path(sequence_dir) / "instances");
    if (!gt_files) return gt_files.status();
    if (gt_files->empty()) {
        return error(StatusCode::kNotFound,
                     sequence_dir + "/instances: no ground-truth <stamp>.png files");
    }
    auto est_files = pngs_by_name(fs::path(run_dir) / "object_masks");
    if (!est_files) return est_files.status();
    for (const auto& [name, gt_file] : *gt_files) {
        // The SLAM run writes a mask for every frame it processed (all zero when no object
        // claimed a pixel): a frame without one was not processed (a run over part of the
        // sequence) and is not scored.
        const auto est_file = est_files->find(name);
        if (est_file == est_files->end()) {
            ++out.frames_without_masks;
            continue;
        }
        auto gt = read_label_png(gt_file);
        if (!gt) return gt.status();
        auto read = read_label_png(est_file->second);
        if (!read) return read.status();
        const cv::Mat est = *read;
        const std::string frame = est_file->second + " (ground truth " + gt_file + ")";
        DF_RETURN_IF_ERROR(out.overlap.add_frame(est, *gt, frame));
        for (const auto& g : out.overlap.ground_truth()) {
            if (!known.count(g.first)) {
                return error(StatusCode::kInvalidArgument,
                             gt_file + ": instance id " + std::to_string(g.first) +
                                 " is not listed in " + sequence_dir + "/instances.json");
            }
        }
    }
    out.gt_frames = gt_files->size();
    for (const auto& e : *est_files) out.masks_without_gt += gt_files->count(e.first) ? 0 : 1;
    return out;
}

}  // namespace df::eval
