// df_eval: score a run as the public benchmarks do.
//   df_eval ate|rpe|object GT EST, recon GT.ply EST.ply, seg GT_SEQ PRED_DIR, timing LOG...,
//   run SEQ_DIR RUN_DIR. See docs/evaluation.md.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdlib>

#include "commands.hpp"
#include "core/log.hpp"

namespace {

using df::eval_cli::Outputs;

/// A number of seconds or metres given on the command line: finite and above (or at) a floor.
CLI::Validator finite_at_least(double floor, bool inclusive) {
    const std::string rule = (inclusive ? ">= " : "> ") + CLI::detail::to_string(floor);
    return CLI::Validator(
        [floor, inclusive, rule](const std::string& text) -> std::string {
            const double v = std::strtod(text.c_str(), nullptr);
            const bool ok = std::isfinite(v) && (inclusive ? v >= floor : v > floor);
            return ok ? "" : "is " + text + ", allowed: finite and " + rule;
        },
        "FINITE " + rule);
}

void add_outputs(CLI::App* sub, Outputs* out, bool with_plot) {
    sub->add_option("--json", out->json_file, "write the results to this JSON file");
    if (with_plot) sub->add_option("--plot", out->plot_file, "write a figure to this PNG file");
}

void add_association(CLI::App* sub, df::eval::AssociationConfig* config) {
    sub->add_option("--max-dt", config->max_difference_s,
                    "seconds: pairs need |t_gt - (t_est + offset)| below this")
        ->capture_default_str()
        ->check(finite_at_least(0, false));
    sub->add_option("--offset", config->offset_s, "seconds added to the estimate's stamps")
        ->capture_default_str()
        ->check(finite_at_least(-1e9, true));
}

/// String choices of the RPE options, turned into the config after parsing.
struct RpeChoices {
    std::string unit = "s";
    std::string form = "tum";
    void apply(df::eval::RpeConfig* config) const {
        config->unit = unit == "f" ? df::eval::DeltaUnit::kFrames : df::eval::DeltaUnit::kSeconds;
        config->form = form == "paper" ? df::eval::RpeForm::kPaper : df::eval::RpeForm::kTumScript;
    }
};

void add_rpe(CLI::App* sub, df::eval::RpeConfig* config, RpeChoices* choices, bool with_form) {
    sub->add_option("--delta", config->delta, "distance of the compared poses, in --unit")
        ->capture_default_str()
        ->check(finite_at_least(0, false));
    sub->add_option("--unit", choices->unit, "s (seconds) or f (frames)")
        ->check(CLI::IsMember({"s", "f"}))
        ->capture_default_str();
    if (with_form) {
        sub->add_option("--form", choices->form,
                        "tum: E = A B^-1 as evaluate_rpe.py; paper: E = B^-1 A (Sturm 2012)")
            ->check(CLI::IsMember({"tum", "paper"}))
            ->capture_default_str();
    }
}

}  // namespace

int main(int argc, char** argv) {
    df::log::set_component("eval");
    CLI::App app{
        "df_eval: score a run against ground truth as the public benchmarks do "
        "(TUM ATE/RPE, Co-Fusion objects, reconstruction, segmentation, timing)"};
    app.require_subcommand(1);
    std::string gt, est;
    Outputs out;

    df::eval::AssociationConfig association;
    auto* ate = app.add_subcommand("ate", "absolute trajectory error (TUM evaluate_ate)");
    ate->add_option("GT", gt, "ground-truth TUM trajectory")->required();
    ate->add_option("EST", est, "estimated TUM trajectory")->required();
    add_association(ate, &association);
    add_outputs(ate, &out, true);

    df::eval::RpeConfig rpe;
    RpeChoices rpe_choices;
    auto* rpe_cmd =
        app.add_subcommand("rpe", "relative pose error (TUM evaluate_rpe, fixed delta)");
    rpe_cmd->add_option("GT", gt, "ground-truth TUM trajectory")->required();
    rpe_cmd->add_option("EST", est, "estimated TUM trajectory")->required();
    add_rpe(rpe_cmd, &rpe, &rpe_choices, true);
    rpe_cmd->add_option("--offset", rpe.offset_s, "seconds added to the estimate's stamps")
        ->capture_default_str()
        ->check(finite_at_least(-1e9, true));
    add_outputs(rpe_cmd, &out, true);

    auto* object = app.add_subcommand("object", "object trajectory aligned by its first pose");
    object->add_option("GT", gt, "ground-truth object trajectory (world_T_object)")->required();
    object->add_option("EST", est, "estimated object trajectory")->required();
    add_association(object, &association);
    add_rpe(object, &rpe, &rpe_choices, false);
    df::eval_cli::ObjectOptions object_options;
    object->add_option("--world", object_options.world,
                       "'tx ty tz qx qy qz qw': gt_T_est of the two worlds (e.g. the camera ATE "
                       "alignment), used instead of aligning the first pose");
    object->add_flag("--body-align", object_options.body_align,
                     "also solve the constant offset of the estimated object frame from the first "
                     "pose pair: est' = W est X (W: --world, or identity)");
    add_outputs(object, &out, true);

    df::eval::ReconstructionConfig recon_config;
    std::string transform;
    auto* recon = app.add_subcommand("recon", "reconstruction accuracy and completeness");
    recon->add_option("GT_PLY", gt, "ground-truth model (PLY points)")->required();
    recon->add_option("EST_PLY", est, "reconstruction (PLY points)")->required();
    recon
        ->add_option("--threshold", recon_config.threshold_m,
                     "metres: a point within this of the other set counts")
        ->capture_default_str();
    recon->add_option("--transform", transform,
                      "'tx ty tz qx qy qz qw': gt_T_est applied to the reconstruction first");
    bool recon_register = false;
    df::eval::RegistrationConfig registration_config;
    recon->add_flag("--register", recon_register,
                    "also register the reconstruction onto the ground truth (trimmed ICP from "
                    "--transform) and score it again: its shape apart from its placement");
    recon
        ->add_option("--register-max-distance", registration_config.max_distance_m,
                     "metres: registration pairs farther apart are left out")
        ->capture_default_str();
    add_outputs(recon, &out, false);

    df::eval::SegmentationConfig seg_config;
    auto* seg = app.add_subcommand("seg", "instance segmentation IoU, precision, recall");
    seg->add_option("GT_SEQ_DIR", gt, "sequence with instances/ and instances.json")->required();
    seg->add_option("PRED_DIR", est, "predicted 16-bit label PNGs named <stamp>.png")->required();
    seg->add_option("--match-iou", seg_config.match_iou,
                    "a segment matches an instance when IoU >= this")
        ->capture_default_str();
    seg->add_flag("--skip-missing", seg_config.skip_missing,
                  "leave out frames without a prediction (default: score them as empty)");
    seg->add_option("--moving", seg_config.moving_min_m,
                    "score an instance only in frames where it moved at least this far (m) "
                    "since the previous frame, by its trajectory (0: every visible frame)")
        ->check(CLI::Range(0.0, 100.0))
        ->capture_default_str();
    add_outputs(seg, &out, false);

    auto* mask = app.add_subcommand(
        "mask", "binary masks (non-zero = in) against ground-truth masks of the same file names");
    mask->add_option("GT_MASK_DIR", gt, "ground-truth masks, <name>.png (e.g. a sequence's masks/)")
        ->required();
    mask->add_option("PRED_DIR", est,
                     "predicted masks or label PNGs of the same names (e.g. a "
                     "run's invalid/)")
        ->required();
    add_outputs(mask, &out, false);

    std::vector<std::string> logs;
    auto* timing = app.add_subcommand(
        "timing",
        "per-stage times from 'timing seq=...' log lines or MCAP recordings of <ns>/stage_status");
    timing->add_option("LOG", logs, "log files or .mcap recordings")->required();
    add_outputs(timing, &out, false);

    df::eval_cli::RunOptions run_options;
    bool no_plots = false, no_align_map = false;
    auto* run = app.add_subcommand(
        "run",
        "score RUN_DIR (trajectory.txt, objects.json or objects/, map.ply, masks/, *.log) "
        "against SEQ_DIR; "
        "writes RUN_DIR/eval.json and RUN_DIR/eval_*.png");
    run->add_option("SEQ_DIR", gt, "sequence folder with ground truth")->required();
    run->add_option("RUN_DIR", est, "run folder")->required();
    add_association(run, &run_options.association);
    run->add_option("--threshold", run_options.reconstruction.threshold_m,
                    "reconstruction threshold in metres")
        ->capture_default_str();
    run->add_option("--object-threshold", run_options.object_model.threshold_m,
                    "object model threshold in metres (objects.json runs)")
        ->capture_default_str()
        ->check(finite_at_least(0, false));
    run->add_option("--min-overlap", run_options.object_association.min_overlap,
                    "an object matches an instance holding at least this fraction of its pixels")
        ->capture_default_str()
        ->check(finite_at_least(0, false));
    run->add_option("--min-frames", run_options.object_association.min_frames,
                    "a rigid instance without an object is missed when visible in this many frames")
        ->capture_default_str();
    run->add_option("--match-iou", run_options.segmentation.match_iou,
                    "segmentation match threshold")
        ->capture_default_str();
    run->add_flag("--no-plots", no_plots, "write no PNG figures");
    run->add_flag("--no-align-map", no_align_map,
                  "score map.ply as written (default: moved by the camera ATE alignment)");

    CLI11_PARSE(app, argc, argv);

    using namespace df::eval_cli;
    rpe_choices.apply(&rpe);
    if (ate->parsed()) return cmd_ate(gt, est, association, out);
    if (rpe_cmd->parsed()) return cmd_rpe(gt, est, rpe, out);
    if (object->parsed()) return cmd_object(gt, est, association, rpe, object_options, out);
    if (recon->parsed())
        return cmd_recon(gt, est, recon_config, transform,
                         recon_register ? std::optional(registration_config) : std::nullopt, out);
    if (seg->parsed()) return cmd_seg(gt, est, seg_config, out);
    if (timing->parsed()) return cmd_timing(logs, out);
    if (mask->parsed()) return cmd_mask(gt, est, out);
    run_options.plots = !no_plots;
    run_options.align_map = !no_align_map;
    return cmd_run(gt, est, run_options);
}
