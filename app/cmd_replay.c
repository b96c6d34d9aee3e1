/* hmdlod replay and hmdlod demo: argument parsing around rpl_run. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/commands.h"
#include "acuity/acuity.h"
#include "bench/bench.h"
#include "replay/replay.h"

static const char replay_usage[] =
    "usage: hmdlod replay --trace FILE|--raw FILE --scene NAME --display NAME|FILE --selector NAME --out DIR\n"
    "                     [--rate HZ] [--frames N] [--capture EVERY] [--objects N] [--seed S]\n"
    "                     [--acuity-scale S] [--render-scale F] [--frequency-reading R] [--quiet]\n"
    "                     [--budget-ms T] [--cost-profile FILE] [--opt-limit-us T] [--static-px N]\n"
    "                     [--cost-correction on|ratio|affine|off] [--within-share P] [--gaze MODEL]\n"
    "                     [--vor-gain G]\n"
    "                     [--vor-latency-ms T] [--fixation-m D] [--saccade-onset-degps V]\n"
    "                     [--reference EVERY] [--velocity-term on|off] [--eccentricity-term on|off]\n"
    "                     [--mb-simplify K] [--foveation off|fixed|gaze] [--periphery-scale S]\n"
    "                     [--inset-deg R] [--blend-deg B]\n"
    "  Replays a head-motion trace on a virtual clock through a scene, rendering both eyes headless.\n"
    "  --trace FILE       hmdlod CSV (t_s,qw,qx,qy,qz[,px,py,pz][,gx,gy,gz]), a Corbillon MMSys'18\n"
    "                     quaternion file, a Nasrabadi MMSys'19 CSV or an EDVAM eye-tracker log (gaze and\n"
    "                     camera pose, read as it is); omitted: the built-in 8 s clip\n"
    "  --raw FILE         a raw tracker recording (hmdlod record), fused as live (not with --trace)\n"
    "  --scene NAME|FILE  built-in scene: field (Reddy's test field), auditorium (Funkhouser's) or domes\n"
    "                     (Mason & Blake's; default field), or a\n"
    "                     scene file (ends in .json, or an existing file: docs/scene-format.md)\n"
    "  --display NAME     built-in display (hmdlod display list) or a JSON profile (default vive)\n"
    "  --selector NAME    none (finest LOD), reddy (acuity-driven, default), static (finest LOD whose\n"
    "                     average triangle covers --static-px pixels), feedback (static's threshold\n"
    "                     steered by measured frame times), fs (Funkhouser-Sequin's cost-bounded\n"
    "                     incremental optimizer, capped by Reddy's acuity: docs/optimizer.md), mb\n"
    "                     (Mason-Blake's on the scene's groups: group impostors drawn for whole groups)\n"
    "  --out DIR          output folder: frames.csv, summary.json, frame_NNNNNN.png (created)\n"
    "  --rate HZ          frame rate of the virtual clock (default: the display's refresh)\n"
    "  --frames N         frames to replay (default: the whole trace)\n"
    "  --capture EVERY    write a stereo PNG every EVERY frames (default 0: none)\n"
    "  --objects N        objects in the field scene (default 100) or domes in domes (default 10)\n"
    "  --seed S           placement seed of the field and domes scenes (default 1)\n"
    "  --acuity-scale S   Reddy's global acuity factor s in (0, 1] (default 1); under contrast a band\n"
    "                     at rho is judged as at rho/s\n"
    "  --visibility C     what decides that lost detail is invisible (docs/visibility.md): contrast\n"
    "                     (default: each lost band's measured contrast against the contrast\n"
    "                     sensitivity function at the eye's adapting luminance) or acuity (Reddy's\n"
    "                     H(v, E), every loss taken at full contrast)\n"
    "  --csf MODEL        contrast sensitivity model: castle (castleCSF, default) or stela (stelaCSF)\n"
    "  --csf-scale K      safety factor on the sensitivity, (0, 1000]: a band is visible when c*S*K >= 1\n"
    "                     (default 2: castleCSF's periphery is less sensitive than foveated image\n"
    "                     metrics'; docs/visibility.md); 1 = the model's threshold\n"
    "  --benefit B        what fs and mb value a level by: funkhouser (default; Funkhouser & Sequin's\n"
    "                     accuracy) or perceptual (the visible contrast it keeps, from the lost-contrast\n"
    "                     spectrum and the CSF; needs --visibility contrast; docs/optimizer.md)\n"
    "  --render-scale F   per-eye resolution factor in (0, 4] (default 1: the display's pixels)\n"
    "  --frequency-reading R  the lost-detail frequency the selector uses: narrow (default; the\n"
    "                     thickness of the thickest feature Reddy's image analysis sees lost), long\n"
    "                     (the longest lost chord) or geometric (R/eps, no rendering); docs/analysis.md\n"
    "  --budget-ms T      frame budget in ms (default: the display's frame period)\n"
    "  --cost-profile FILE  machine cost profile from hmdlod calibrate (default: the built-in one\n"
    "                     for llvmpipe)\n"
    "  --opt-limit-us T   stop fs or mb after T microseconds per frame (default 0: run to the end); the\n"
    "                     choice is feasible after every iteration (Nirenstein et al. 5.5)\n"
    "  --static-px N      static's pixels per triangle (default 64); feedback starts from it\n"
    "  --saccade-onset-degps V  gaze speed that starts a saccade (default 100; the end is at half of it)\n"
    "  --cost-correction on|ratio|affine|off  correct fs's and mb's budget from measured draw times: an\n"
    "                     affine fit measured = a + b x by recursive least squares (x: the objects'\n"
    "                     predicted cost; on = affine, the default), or the smoothed measured/predicted\n"
    "                     ratio, which divides the whole budget (docs/cost-model.md)\n"
    "  --within-share P   the share of frames the affine correction's margin aims to keep within the\n"
    "                     budget, in (0.5, 1) (default 0.97: the margin is that quantile of the last\n"
    "                     192 frames' errors of the fitted cost; above 0.97 only where the tail\n"
    "                     continues the body, docs/cost-model.md)\n"
    "  --gaze MODEL       how the eye moves (docs/gaze.md): auto (default: tracked when the trace has\n"
    "                     gaze columns, else vor), head (eye fixed in the head, Reddy's assumption),\n"
    "                     vor (the eye holds a world point ahead of the head), tracked (the trace's gaze)\n"
    "  --vor-gain G       VOR gain in [0, 1.2] (default 0.95)\n"
    "  --vor-latency-ms T VOR latency in [0, 100] ms (default 10)\n"
    "  --fixation-m D     distance of the VOR's fixated point, > 0 m (default: the median distance\n"
    "                     from the first eye position to the objects, clamped to [0.5, 50] m)\n"
    "  --reference EVERY  every EVERY frames, also draw the frame at full detail (selector none, same\n"
    "                     pose and eyes, after it was timed) and write PSNR, SSIM, foveated SSIM and\n"
    "                     the predicted visible error to frames.csv and the summary (docs/replay-output.md)\n"
    "  --velocity-term on|off      off: every object is taken as still on the retina (Reddy's size +\n"
    "                     eccentricity only); default on\n"
    "  --eccentricity-term on|off  off: every object is taken as at the gaze centre; default on\n"
    "  --mb-simplify K    mb: apply Nirenstein et al.'s hierarchy simplification K times (default 0):\n"
    "                     groups at most K deep become leaves choosing their impostor or all their\n"
    "                     objects at one shared level — a cheaper optimizer, coarser choices\n"
    "  --quiet            no summary table on stdout\n";

/* Parses the options replay and demo share, and the demo's --repeats when `repeats` is not NULL;
 * returns 0, or 1 after printing the message. */
static int parse_replay_options(int argc, char **argv, struct rpl_options *o, long *repeats, const char *usage)
{
    for (int i = 1; i < argc; ++i) {
        const char *opt = argv[i];
        const char *val = i + 1 < argc ? argv[i + 1] : NULL;
        long n = 0;
        double d = 0.0;
        int bad = 0;
        if (!strcmp(opt, "--quiet")) {
            o->frame.quiet = 1;
            continue;
        }
        if (!val) {
            fprintf(stderr, "hmdlod: %s needs a value\n", opt);
            return 1;
        }
        ++i;
        if (!strcmp(opt, "--trace"))
            o->trace_path = val;
        else if (!strcmp(opt, "--raw"))
            o->raw_path = val;
        else if (!strcmp(opt, "--scene"))
            o->frame.scene = val;
        else if (!strcmp(opt, "--display"))
            o->frame.display = val;
        else if (!strcmp(opt, "--selector"))
            o->frame.selector = val;
        else if (!strcmp(opt, "--frequency-reading"))
            o->frame.frequency_reading = val;
        else if (!strcmp(opt, "--visibility"))
            o->frame.visibility = val;
        else if (!strcmp(opt, "--csf"))
            o->frame.csf = val;
        else if (!strcmp(opt, "--benefit"))
            o->frame.benefit = val;
        else if (!strcmp(opt, "--out"))
            o->out_dir = val;
        else if (repeats && !strcmp(opt, "--repeats")) {
            if (app_parse_long(opt, val, 1, BCH_MAX_REPEATS, repeats))
                return 1;
        }
        else if (!strcmp(opt, "--rate")) {
            if (app_parse_double(opt, val, &o->rate_hz))
                return 1;
        } else if (!strcmp(opt, "--frames")) {
            if (app_parse_long(opt, val, 1, 100000000, &o->frames))
                return 1;
        } else if (!strcmp(opt, "--capture")) {
            if (app_parse_long(opt, val, 0, 100000000, &o->capture_every))
                return 1;
        } else if (!strcmp(opt, "--objects")) {
            if (app_parse_long(opt, val, 1, 100000, &n))
                return 1;
            o->frame.object_count = (int)n;
        } else if (!strcmp(opt, "--seed")) {
            if (app_parse_long(opt, val, 0, 2147483647, &n))
                return 1;
            o->frame.seed = (uint64_t)n;
        } else if (!strcmp(opt, "--acuity-scale")) {
            if (app_parse_double(opt, val, &d))
                return 1;
            o->frame.acuity_scale = d;
        } else if (!strcmp(opt, "--csf-scale")) {
            if (app_parse_double(opt, val, &d))
                return 1;
            o->frame.csf_scale = d;
        } else if (!strcmp(opt, "--budget-ms")) {
            if (app_parse_double(opt, val, &d))
                return 1;
            if (!(d > 0.0)) {
                fprintf(stderr, "hmdlod: --budget-ms: %s is not a positive number of milliseconds\n", val);
                return 1;
            }
            o->frame.budget_ms = d;
        } else if (!strcmp(opt, "--cost-profile")) {
            o->frame.cost_profile = val;
        } else if (!strcmp(opt, "--opt-limit-us")) {
            if (app_parse_double(opt, val, &o->frame.opt_limit_us))
                return 1;
        } else if (!strcmp(opt, "--static-px")) {
            if (app_parse_double(opt, val, &o->frame.static_px_per_triangle))
                return 1;
        } else if (!strcmp(opt, "--saccade-onset-degps")) { /* frame/saccade_step.c */
            if (app_parse_double(opt, val, &o->frame.saccade_onset_degps))
                return 1;
            if (!(o->frame.saccade_onset_degps > 0.0 && o->frame.saccade_onset_degps < 1e5)) {
                fprintf(stderr, "hmdlod: --saccade-onset-degps: %s is not a speed in (0, 1e5) deg/s\n", val);
                return 1;
            }
        } else if (!strcmp(opt, "--cost-correction")) {
            if (!strcmp(val, "ratio"))
                o->frame.cost_correction = FRM_CORRECTION_RATIO;
            else if (!strcmp(val, "on") || !strcmp(val, "affine"))
                o->frame.cost_correction = FRM_CORRECTION_AFFINE;
            else if (!strcmp(val, "off"))
                o->frame.cost_correction = FRM_CORRECTION_OFF;
            else {
                fprintf(stderr, "hmdlod: --cost-correction: '%s' is not on, ratio, affine or off\n", val);
                return 1;
            }
        } else if (!strcmp(opt, "--within-share")) { /* its range: frm_options_check */
            if (app_parse_double(opt, val, &o->frame.within_share))
                return 1;
        } else if (!strcmp(opt, "--gaze")) {
            enum acu_gaze_model model;
            if (strcmp(val, "auto") && acu_gaze_model_parse(val, &model) != 0) {
                fprintf(stderr, "hmdlod: --gaze: '%s' is not a gaze model (auto, head, vor, tracked)\n", val);
                return 1;
            }
            o->frame.gaze = val;
        } else if (!strcmp(opt, "--vor-gain")) {
            if (app_parse_double(opt, val, &d))
                return 1;
            if (!(d >= 0.0 && d <= 1.2)) {
                fprintf(stderr, "hmdlod: --vor-gain: %s is outside [0, 1.2]\n", val);
                return 1;
            }
            o->frame.vor_gain = d;
        } else if (!strcmp(opt, "--vor-latency-ms")) {
            if (app_parse_double(opt, val, &d))
                return 1;
            if (!(d >= 0.0 && d <= 100.0)) {
                fprintf(stderr, "hmdlod: --vor-latency-ms: %s is outside [0, 100] ms\n", val);
                return 1;
            }
            o->frame.vor_latency_ms = d;
        } else if (!strcmp(opt, "--fixation-m")) {
            if (app_parse_double(opt, val, &d))
                return 1;
            if (!(d > 0.0 && d <= 1e6)) {
                fprintf(stderr, "hmdlod: --fixation-m: %s is not a distance in (0, 1e6] m\n", val);
                return 1;
            }
            o->frame.fixation_m = d;
        } else if (!strcmp(opt, "--reference")) {
            if (app_parse_long(opt, val, 0, 100000000, &o->reference_every))
                return 1;
        } else if (!strcmp(opt, "--mb-simplify")) {
            if (app_parse_long(opt, val, 0, 8, &n))
                return 1;
            o->frame.mb_simplify = (int)n;
        } else if (!strcmp(opt, "--velocity-term") || !strcmp(opt, "--eccentricity-term")) {
            int off = !strcmp(val, "off");
            if (!off && strcmp(val, "on")) {
                fprintf(stderr, "hmdlod: %s: '%s' is not on or off\n", opt, val);
                return 1;
            }
            if (opt[2] == 'v')
                o->frame.velocity_term_off = off;
            else
                o->frame.eccentricity_term_off = off;
        } else if (!strcmp(opt, "--render-scale")) {
            if (app_parse_double(opt, val, &d))
                return 1;
            o->frame.render_scale = d;
        } else if (app_parse_layer_option(opt, val, &o->frame, &bad)) {
            if (bad)
                return 1;
        } else {
            fprintf(stderr, "hmdlod: unknown option '%s'\n%s", opt, usage);
            return 1;
        }
    }
    if (o->trace_path && o->raw_path) {
        fprintf(stderr, "hmdlod: --trace and --raw exclude each other: give one head-motion input\n");
        return 1;
    }
    return 0;
}

static int run_and_report(const struct rpl_options *o, struct rpl_summary *summary)
{
    struct hl_error err;
    if (rpl_run(o, summary, &err) != 0) {
        fprintf(stderr, "hmdlod: %s\n", err.msg);
        return 1;
    }
    return 0;
}

int cmd_replay(int argc, char **argv)
{
    if (app_wants_help(argc, argv)) {
        fputs(replay_usage, stdout);
        fputs(app_layer_usage, stdout);
        return 0;
    }
    struct rpl_options o;
    rpl_options_defaults(&o);
    if (parse_replay_options(argc, argv, &o, NULL, replay_usage) != 0)
        return 1;
    if (!o.out_dir) {
        fprintf(stderr, "hmdlod replay: --out DIR is required\n%s", replay_usage);
        return 1;
    }
    struct rpl_summary summary;
    int rc = run_and_report(&o, &summary);
    if (rc == 0 && !o.frame.quiet)
        printf("  wrote %s/frames.csv and %s/summary.json\n", o.out_dir, o.out_dir);
    return rc;
}

static const char demo_usage[] =
    "usage: hmdlod demo [--out DIR] [--repeats N] [replay options]\n"
    "  Replays the built-in 8 s head-motion clip (still, looking around, a fast turn) through the\n"
    "  built-in field scene on the built-in Vive profile, headless, three times: every object at its\n"
    "  finest LOD (selector none), Reddy's acuity model alone (reddy), and Funkhouser-Sequin's\n"
    "  cost-bounded optimizer capped by Reddy's acuity (fs) holding the display's frame budget.\n"
    "  Prints the summaries and a comparison; writes DIR/none, DIR/reddy and DIR/fs (frames.csv,\n"
    "  summary.json, stereo PNGs every 60 frames). Default DIR: hmdlod-demo. Then measures the frame\n"
    "  times and the ratios none/reddy and none/fs again from N alternated repeats in the same process\n"
    "  (none, reddy, fs | fs, reddy, none | ...; each session opened fresh, nothing kept), and prints\n"
    "  them as the median over the repeats with min-max, and how they were measured.\n"
    "  --repeats N        alternated repeats for the frame times and ratios, 1..100 (default 2: the\n"
    "                     fewest in which each selector runs first as often as last)\n"
    "  Any replay option may be added (see hmdlod replay --help); --selector is ignored.\n";

enum { DEMO_RUNS = 3 };
static const char *const demo_selectors[DEMO_RUNS] = {"none", "reddy", "fs"};

/* The ratios of the demo from alternated repeats (bench/alternate.c): the output round's sessions
 * ran one after another from a fresh process, so none paid the process's warm-up and reddy and fs
 * whatever the load did next; ratios taken there follow run order, not the selectors. */
static int demo_repeats(const struct rpl_options *o, long repeats)
{
    struct rpl_options configs[DEMO_RUNS];
    for (int k = 0; k < DEMO_RUNS; ++k) {
        configs[k] = *o;
        configs[k].frame.selector = demo_selectors[k];
        configs[k].capture_every = 0; /* the output round has the PNGs; captures are outside the timing */
    }
    struct rpl_summary *sums = calloc((size_t)repeats * DEMO_RUNS, sizeof *sums);
    if (!sums) {
        fprintf(stderr, "hmdlod demo: out of memory\n");
        return 1;
    }
    if (bch_alternate_run(configs, DEMO_RUNS, (int)repeats, sums, o->frame.quiet ? NULL : "hmdlod demo") != 0) {
        free(sums);
        return 1;
    }
    printf("\nframe time from %ld alternated repeat%s (ms, mean over frames 1…; median over the repeats, min–max):\n",
           repeats, repeats == 1 ? "" : "s");
    for (int k = 0; k < DEMO_RUNS; ++k) {
        struct bch_spread m;
        bch_mean_spread(sums, DEMO_RUNS, (int)repeats, k, &m);
        printf("  %-10s %8.2f   %.2f–%.2f\n", demo_selectors[k], m.median, m.min, m.max);
    }
    for (int k = 1; k < DEMO_RUNS; ++k) {
        struct bch_spread r;
        bch_ratio_spread(sums, DEMO_RUNS, (int)repeats, 0, k, &r);
        printf("  none/%-5s %7.2fx   %.2f–%.2f\n", demo_selectors[k], r.median, r.min, r.max);
    }
    char order[128];
    bch_alternate_order(DEMO_RUNS, demo_selectors, order, sizeof order);
    printf("  measured: %ld alternated repeat%s in one process after the output round (which warms it up), "
           "order %s, each session opened fresh, frame 0 left out, ratio = median of per-repeat ratios "
           "[min–max]\n",
           repeats, repeats == 1 ? "" : "s", order);
    free(sums);
    return 0;
}

int cmd_demo(int argc, char **argv)
{
    if (app_wants_help(argc, argv)) {
        fputs(demo_usage, stdout);
        return 0;
    }
    struct rpl_options o;
    rpl_options_defaults(&o);
    o.capture_every = 60;
    o.out_dir = "hmdlod-demo";
    long repeats = 2;
    if (parse_replay_options(argc, argv, &o, &repeats, demo_usage) != 0)
        return 1;
    const char *base_dir = o.out_dir;
    struct rpl_summary summaries[DEMO_RUNS];
    char dirs[DEMO_RUNS][4096];
    for (int k = 0; k < DEMO_RUNS; ++k) {
        snprintf(dirs[k], sizeof dirs[k], "%s/%s", base_dir, demo_selectors[k]);
        o.frame.selector = demo_selectors[k];
        o.out_dir = dirs[k];
        if (run_and_report(&o, &summaries[k]) != 0)
            return 1;
    }
    const struct rpl_summary *none = &summaries[0];
    printf("\non the same frames (budget %.2f ms, cost model: %s; frame ms: one session each, in this order):\n",
           summaries[2].budget_ms, summaries[2].cost_profile);
    printf("  %-10s %16s %14s %14s %18s\n", "selector", "triangles/eye", "vs none", "frame ms mean",
           "within budget");
    for (int k = 0; k < DEMO_RUNS; ++k) {
        const struct rpl_summary *s = &summaries[k];
        printf("  %-10s %16.0f %13.2fx %14.2f %17.1f %%\n", demo_selectors[k], s->triangles_per_eye_mean,
               s->triangles_per_eye_mean > 0 ? none->triangles_per_eye_mean / s->triangles_per_eye_mean : 0.0,
               s->frame_ms_mean, 100.0 * s->deadline_met_fraction);
    }
    printf("  fs: predicted cost within the budget on %.1f %% of frames; benefit %.4f of the LP bound\n",
           100.0 * summaries[2].predicted_within_fraction, summaries[2].benefit_share_of_lp_mean);
    printf("  output: %s/none, %s/reddy and %s/fs (frames.csv, summary.json, frame_*.png)\n", base_dir, base_dir,
           base_dir);
    o.out_dir = base_dir;
    return demo_repeats(&o, repeats);
}
