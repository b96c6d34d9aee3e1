/* replay: recorded head motion on a virtual clock. Head-motion trace formats (the project's CSV,
 * Corbillon MMSys'18, Nasrabadi MMSys'19, the EDVAM eye-tracker log), resampling by slerp with sane
 * angular velocity, the trace pose source, the replay run (frame/'s frame at each tick of the
 * virtual clock), per-frame CSV and summaries (table + JSON). Prefix rpl_. It runs frame/ and may
 * not touch live/ or bench/. */
#ifndef HMDLOD_REPLAY_H
#define HMDLOD_REPLAY_H

#include <stdio.h>

#include "base/base.h"
#include "tracking/tracking.h"
#include "frame/frame.h"

/* ---- traces --------------------------------------------------------------------------------- */
enum rpl_trace_format {
    RPL_TRACE_HMDLOD_CSV = 0,
    RPL_TRACE_CORBILLON = 1,
    RPL_TRACE_NASRABADI = 2,
    RPL_TRACE_EDVAM = 3 /* EDVAM eye-tracker log: camera pose + 3D point of gaze (docs/trace-format.md §2c) */
};

/* What loading found and did (docs/trace-format.md lists each rule). */
struct rpl_trace_report {
    size_t rows;              /* data rows read */
    size_t sign_flips;        /* q → −q to stay in the previous sample's hemisphere */
    size_t repeated_samples;  /* rows whose orientation repeats the previous row exactly (kept) */
    size_t gaps;              /* steps longer than RPL_TRACE_GAP_S */
    double longest_gap_s;
    size_t speed_outliers;    /* samples whose step speed exceeds RPL_TRACE_OUTLIER_DEGPS (marked) */
    double max_step_speed_degps;
    size_t repeated_timestamps; /* rows whose time equalled the previous row's (spread, kept) */
    size_t timestamp_runs;    /* runs of ≥ 2 rows sharing one time */
    double timestamp_step_s;  /* median step between distinct times, the spread's limit; 0 if no runs */
    size_t low_confidence_gaze; /* EDVAM: rows without a measured gaze (interpolated from neighbours) */
    size_t placeholder_rows;  /* EDVAM: leading placeholder rows skipped (C = 0, F = (0,0,1)) */
    size_t held_orientations; /* EDVAM: forward within RPL_EDVAM_VERTICAL_DEG of vertical: previous kept */
};
#define RPL_TRACE_GAP_S 0.1
#define RPL_MAX_FRAMES 100000000L        /* frames one replay may hold (as --frames): 12.9 days at 90 Hz */
#define RPL_TRACE_OUTLIER_DEGPS 1000.0   /* above physiological head turns (traces peak at 600–800 deg/s) */
#define RPL_TRACE_UNIT_TOLERANCE 1e-3    /* | |q| − 1 | beyond this is an error, not renormalised */
#define RPL_EDVAM_MIN_CONFIDENCE 0.8     /* Pupil confidence below this: no measured gaze (data README §3) */
#define RPL_EDVAM_VERTICAL_DEG 10.0      /* forward this close to ±Y has no usable yaw (0.1 rounding: 5.7°/step) */

/* A loaded trace: times strictly increasing, orientations unit and hemisphere-continuous,
 * body-to-world in the project frame (+Y up, −Z forward). Arrays owned by the trace. */
struct rpl_trace {
    enum rpl_trace_format format;
    size_t count;
    double *time_s;
    hl_quatd *orientation;
    hl_vec3d *position_m;   /* NULL when the trace has none */
    hl_vec3d *gaze_dir;     /* head frame, unit; NULL when the trace has none */
    unsigned char *outlier; /* 1 where the sample was a speed outlier (excluded from velocity) */
    struct rpl_trace_report report;
};

/* One line (no newline) describing what loading did: rows, flips, repeats, gaps, outliers, repeated
 * timestamps and, for eye-tracker logs, the gaze counts. Always NUL-terminates buf (size > 0). */
void rpl_trace_report_format(const struct rpl_trace_report *r, char *buf, size_t size);

/* Parses a whole file held in memory; `name` labels messages ("name:line: reason"). Pure: no I/O.
 * Detects the format from the header line. On error returns −1 and frees what it allocated. */
int rpl_trace_parse(const char *text, size_t length, const char *name, struct rpl_trace *out,
                    struct hl_error *err);
int rpl_trace_load(const char *path, struct rpl_trace *out, struct hl_error *err);
void rpl_trace_free(struct rpl_trace *trace);

/* The built-in clip for `hmdlod demo`: 8 s of synthetic head motion (still, slow look-around, a fast
 * 270 deg/s turn, still) at 60 Hz in the project's format. */
int rpl_trace_builtin_clip(struct rpl_trace *out, struct hl_error *err);

/* A raw tracker recording (docs/raw-recording.md) as a trace: every report goes through trk_stream,
 * the parser and fusion a live session uses; one row per report that fused a sample, at that
 * report's newest sample time (device clock, first row at 0 s), holding the fused body-to-world
 * orientation. The report is filled as a parsed file's. A torn tail and reports the parser rejects
 * are skipped with a note on stderr (a live session skips them too); a corrupt record in the middle
 * or a bad header is an error naming the file and byte offset. */
int rpl_trace_from_recording(const char *path, struct rpl_trace *out, struct hl_error *err);
/* Writes t in the project's CSV (docs/trace-format.md §1; %.9f time, %.17g quaternion, position
 * and gaze columns when present) to path via a temporary file and rename: never a partial file. */
int rpl_trace_write_csv(const struct rpl_trace *t, const char *path, struct hl_error *err);

/* Orientation at t (slerp between neighbours, clamped to the ends), angular and linear velocity
 * (world, rad/s and m/s) from a ±RPL_VELOCITY_HALF_WINDOW_S window that skips outliers and bridges
 * gaps, and the world gaze's angular velocity from a ±RPL_GAZE_VELOCITY_HALF_WINDOW_S window
 * (docs/trace-format.md §4: a 10 ms span keeps a saccade's peak, 50 ms would smear it). No allocation. */
#define RPL_VELOCITY_HALF_WINDOW_S 0.025
#define RPL_GAZE_VELOCITY_HALF_WINDOW_S 0.005
void rpl_trace_sample(const struct rpl_trace *trace, double time_s, struct trk_pose *out);

/* A pose source over a trace (takes ownership of *trace's arrays; zeroes *trace). */
int rpl_trace_source_create(struct rpl_trace *trace, struct trk_pose_source **out, struct hl_error *err);

/* ---- the replay run ------------------------------------------------------------------------- */
/* A replay: the session's options (frame/frame.h) and where its head motion comes from and goes. */
struct rpl_options {
    struct frm_options frame; /* scene, display, selector, budget, gaze …; quiet also hides the summary table */
    const char *trace_path;  /* NULL → built-in clip */
    const char *raw_path;    /* raw tracker recording fused into the trace (excludes trace_path) */
    const char *out_dir;     /* created if missing */
    double rate_hz;          /* 0 → the display's refresh */
    long frames;             /* 0 → the whole trace */
    long capture_every;      /* 0 → no PNG; N → frames 0, N, 2N … */
    /* Image error (render/image_error.h; docs/replay-output.md): 0 → none; N → frames 0, N, 2N … are
     * also drawn at full detail (selector none, same pose and eyes) after being timed, and both images
     * are compared: PSNR, SSIM, foveated SSIM around the frame's gaze. */
    long reference_every;
};
void rpl_options_defaults(struct rpl_options *o);
/* frm_options_check, then the replay's own: an output folder (when need_out_dir), the rate, frame,
 * capture and reference counts. 0, or −1 with err naming the option. */
int rpl_options_check(const struct rpl_options *o, int need_out_dir, enum frm_selector *selector,
                      enum frm_freq_reading *reading, struct hl_error *err);

/* Head-speed bands of the summary, deg/s: [0,10) [10,30) [30,60) [60,120) [120,∞). */
enum { RPL_SPEED_BAND_COUNT = 5 };
extern const double rpl_speed_band_lower_degps[RPL_SPEED_BAND_COUNT];

struct rpl_summary {
    long frames;
    double frame_ms_mean, frame_ms_max, frame_ms_stddev;
    double frame_ms_median, frame_ms_p95, frame_ms_p99; /* nearest-rank percentiles */
    /* The mean over frames 1… (NaN for a one-frame run): frame 0 pays the GL driver's shader
     * compiles, about ten frames' worth on llvmpipe, and would tilt ratios between runs. */
    double frame_ms_mean_after_first;
    double draw_ms_mean, draw_ms_median, acuity_us_mean, select_us_mean;
    double triangles_per_eye_mean;
    double triangles_relative_to_none; /* mean triangles / mean finest-LOD triangles of the same frames */
    double deadline_met_fraction;
    double acuity_evaluations_mean;
    double visible_mean;
    double cull_groups_tested_mean, cull_instances_tested_mean; /* scn_cull's sphere tests per frame */
    uint32_t scene_instances, scene_groups;
    long vm_hwm_kib, vm_rss_kib; /* resident memory at the end (/proc/self/status VmHWM, VmRSS); −1 unknown */
    double minor_faults_per_frame; /* mean over the steady-state frames; NaN: none */
    long minor_faults_from_frame;  /* the first of them: a tenth into the run (at least frame 1) */
    double budget_ms;
    /* against the budget (DESIGN.md "One frame" step 7; issue: frames that hold their rate) */
    double frame_ms_stddev_share_of_budget, frame_ms_p99_share_of_budget;
    double predicted_within_fraction;  /* frames whose predicted cost ≤ budget */
    double truncated_fraction, over_budget_fraction; /* optimizer stopped at its limit; cheapest set did not fit */
    double dropped_mean;               /* objects dropped per frame (fs, mb; 0 for the other selectors) */
    double dropped_px_share_mean, dropped_px_share_max; /* the dropped objects' share of the visible pixels */
    long underused_drops;              /* frames that spent under 70 % of the optimizer's budget while an object
                                        * they dropped would have fit (frm_select_record.underused_drop) */
    double lod_changes_per_object_s;   /* popping: level changes per visible object per second */
    double optimizer_us_mean, optimizer_us_max, iterations_mean;
    double benefit_share_of_lp_mean, benefit_share_of_lp_min; /* NaN when not measured */
    double rate_hz;
    char cost_profile[160];
    char cost_correction[16];         /* "affine", "ratio" or "off": how fs and mb corrected their budget */
    double within_share;              /* affine: the share of frames its margin aims to keep within the budget */
    long band_frames[RPL_SPEED_BAND_COUNT];
    double band_triangle_share[RPL_SPEED_BAND_COUNT]; /* triangles drawn / finest, per band */
    /* Σ triangles drawn / Σ finest over the visible objects of every frame, by the object's
     * eccentricity band (rnd_ecc_band_lower_deg) and retinal-speed band (frm_retinal_band_lower_degps);
     * NaN where no object fell in the band. */
    double ecc_triangle_share[RND_ECC_BANDS], retinal_triangle_share[FRM_RETINAL_BANDS];
    /* the gaze model used (acuity/gaze.h) and its parameters; the eye's mean angular speed */
    char gaze[16];
    double fixation_m, vor_gain, vor_latency_ms;
    double neck_to_eye_m[2];   /* the display's, used where the trace has no positions */
    int trace_has_position, trace_has_gaze;
    double eye_speed_degps_mean;
    char renderer[128];
    char selector[16], scene[256], display[64];
    /* foveated layers (frame/layers.h): the mode, frames per periphery scale (frm_layer_scales: index
     * 0 is the plain frame), frames whose setting lost visible detail, and over the layered frames the
     * mean inset radius and the composite's mean time (the compositor's pass, not in frame_ms) */
    char foveation[16];
    long scale_frames[FRM_LAYER_SCALES], lossy_frames;
    double inset_radius_deg_mean, composite_ms_mean, scale_mean; /* scale_mean: of the layered frames' scales */
    /* When and where the frames ran: the wall clock (CLOCK_REALTIME, s since 1970) before the first
     * frame and after the last, and the host's name ("" unknown). A report merging many runs tells
     * from these which ran at the same time on one machine (their timings shared it). */
    double wall_start_unix_s, wall_end_unix_s;
    char host[64];
    /* saccades (frame/saccade_step.c; docs/gaze.md), only when the trace has gaze (gaze_frames > 0) */
    long gaze_frames, saccades, suppressed_frames;
    double suppressed_fraction;           /* frames inside a saccade or its window / frames */
    long refine_miss_frames, refine_missed_saccades; /* frames past the 28 ms deadline; saccades with one */
    double refine_missed_saccade_fraction; /* refine_missed_saccades / saccades (0 without saccades) */
    /* Predicted visible error, every frame: the share of the visible objects' projected pixels whose
     * object is drawn coarser than its perceptual ceiling (or dropped, or left to a group impostor). */
    double visible_error_mean, visible_error_max;
    /* The visibility criterion (docs/visibility.md): "contrast" or "acuity"; under contrast the CSF
     * model, k, the display's peak luminance, the adapting luminance over the frames (NaN under
     * acuity) and how often its table was refilled. */
    char visibility[16], csf[16];
    double csf_scale, peak_luminance_cdm2;
    double adapting_luminance_cdm2_mean, adapting_luminance_cdm2_min, adapting_luminance_cdm2_max;
    long csf_table_refills;
    char benefit[16]; /* what fs and mb valued levels by: "funkhouser" or "perceptual" (--benefit) */
    /* Measured image error against the full-detail frame (--reference), over the compared frames;
     * all NaN when none were compared. PSNR over the RGB channels (+inf for an identical frame, which
     * the mean leaves out and identical_frames counts); SSIM on luminance (Wang et al. 2004, Gaussian
     * 11×11, σ 1.5), ssim_rgb the mean of the per-channel SSIMs; fssim weighted by Reddy's M(E) around
     * the frame's gaze; fssim_band per eccentricity band (RND_ECC_BANDS); p5: 5th percentile. */
    long reference_frames, identical_frames;
    double psnr_db_mean, psnr_db_min, psnr_db_p5;
    double ssim_mean, ssim_min, ssim_p5, ssim_rgb_mean;
    double fssim_mean, fssim_min, fssim_p5;
    double fssim_band_mean[4];
    double px_over_32_share_mean;          /* pixels with a channel off by more than 32 levels */
    double visible_error_reference_mean;   /* predicted visible error over the compared frames only */
    /* LDR-FLIP (render/flip.h) at flip_ppd, the eye images' centre: the mean and weighted median of
     * each frame's error map, averaged over the compared frames; the largest frame mean; the largest
     * pixel error of any compared frame. */
    double flip_ppd, flip_mean, flip_median_mean, flip_mean_max, flip_max;
};

/* Runs the replay and writes DIR/frames.csv, DIR/summary.json and PNG captures. */
int rpl_run(const struct rpl_options *o, struct rpl_summary *summary, struct hl_error *err);
void rpl_summary_print(FILE *f, const struct rpl_summary *s);

/* ---- memory (replay/output.c) ---------------------------------------------------------------- */
/* Peak and current resident set of this process in KiB (VmHWM, VmRSS of /proc/self/status); −1 each
 * where the file or the line is missing (not Linux). */
void rpl_resident_memory(long *vm_hwm_kib, long *vm_rss_kib);

#endif
