/* The live session (DESIGN.md "One frame", live use): the same frame function as replay draws both
 * eyes into the renderer's FBO, the distortion pass draws them to the window, and the loop runs on
 * the wall clock at the display's refresh. Each frame's pose is asked of the pose source for that
 * frame's display time (its slot), so a tracker source predicts to it (tracking/hid.h). */
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>

#include "live/live.h"

static volatile sig_atomic_t live_interrupted;
static void live_on_signal(int sig)
{
    (void)sig;
    live_interrupted = 1;
}

void liv_options_defaults(struct liv_options *o)
{
    memset(o, 0, sizeof *o);
    o->device = "auto";
    o->monitor = -1;
    o->yaw_degps = 0.0;
}

/* The head trace CSV (docs/trace-format.md): replayable with hmdlod replay --trace. */
static int trace_open(struct liv_record *r, const char *path, struct hl_error *err)
{
    return liv_record_open(r, path, "t_s,qw,qx,qy,qz\n", err);
}

/* With a tracker, --record FILE also keeps the raw reports (tracking/recording.h) in FILE with
 * .csv replaced by .raw (or .raw appended): `hmdlod replay --raw` replays them through the parser
 * and fusion again. */
static void raw_path_of(const char *csv, char *out, size_t size)
{
    size_t n = strlen(csv);
    if (n > 4 && strcmp(csv + n - 4, ".csv") == 0)
        snprintf(out, size, "%.*s.raw", (int)(n - 4), csv);
    else
        snprintf(out, size, "%s.raw", csv);
}

/* The pose source: a tracker (auto: the first found, else the desk), or the desk with --device none. */
static int open_source(const struct liv_options *o, struct trk_pose_source **src, int *is_desk,
                       struct hl_error *err)
{
    *src = NULL;
    *is_desk = 0;
    const char *dev = o->device ? o->device : "auto";
    if (strcmp(dev, "none") != 0) {
        struct hl_error terr = {""};
        if (trk_tracker_source_create(strcmp(dev, "auto") == 0 ? NULL : dev, 0.0, src, &terr) == 0 &&
            (*src)->start(*src, &terr) == 0)
            return 0;
        trk_source_destroy(*src);
        *src = NULL;
        if (strcmp(dev, "auto") != 0)
            return hl_fail(err, "--device %s: %s", dev, terr.msg);
        fprintf(stderr, "hmdlod: note: no tracker opened (%s); mouse and keys look instead\n", terr.msg);
    }
    *is_desk = 1;
    return liv_desk_source_create(hl_clock_now_s(), o->yaw_degps, src, err);
}

/* Windowed at a desk: the display's two eyes, scaled down to fit 90% of the primary monitor. */
static void window_size(const struct hmd_profile *p, int *w, int *h)
{
    struct rnd_monitor_info m[8];
    struct hl_error err = {""};
    int n = rnd_monitor_list(m, 8, &err);
    double full_w = 2.0 * p->eye_width_px, full_h = p->eye_height_px, scale = 1.0;
    if (n > 0 && m[0].width_px > 0 && m[0].height_px > 0)
        scale = fmin(1.0, fmin(0.9 * m[0].width_px / full_w, 0.9 * m[0].height_px / full_h));
    *w = (int)lround(full_w * scale) & ~1; /* even: two equal eye halves */
    *h = (int)lround(full_h * scale);
}

/* Whether glfwSwapInterval(1) throttles here: time a few swaps of an empty frame. */
static int swap_throttles(struct rnd_window *w, double period_ms)
{
    rnd_window_set_swap_interval(w, 1);
    rnd_window_swap(w);
    int64_t t0 = hl_clock_now_ns();
    enum { N = 6 };
    for (int i = 0; i < N; ++i)
        rnd_window_swap(w);
    double mean_ms = (double)(hl_clock_now_ns() - t0) * 1e-6 / N;
    return mean_ms > 0.6 * period_ms;
}

static int capture_write(struct rnd_window *w, const char *path, struct hl_error *err)
{
    int width, height;
    rnd_window_size(w, &width, &height);
    uint8_t *rgba = malloc((size_t)width * (size_t)height * 4);
    if (!rgba)
        return hl_fail(err, "capture: out of memory");
    int rc = rnd_window_read_rgba(w, rgba, err) == 0 ? rnd_png_write(path, rgba, width, height, err) : -1;
    free(rgba);
    return rc;
}

struct live_state {
    struct frm_session s;
    struct rnd_window *window;
    struct rnd_distortion *distortion;
    struct liv_record record;
    struct liv_record log; /* --log: one row per frame (docs/live.md) */
    struct liv_series present_ms, frame_ms, distortion_ms, to_present_ms;
    struct liv_series on_time_ms; /* intervals ending in a frame that made its slot (and followed one that did) */
    int is_desk, tracker_lost, tracker_seen_ok, want_capture, started_mb;
    long captures;
    double triangles_sum, optimizer_sum;
};

/* S: the next selector (mb only when the session started with it: it needs the groups' state). */
static const enum frm_selector live_selectors[] = {FRM_SELECT_NONE, FRM_SELECT_REDDY, FRM_SELECT_STATIC,
                                                   FRM_SELECT_FEEDBACK, FRM_SELECT_FS, FRM_SELECT_MB};
static const char *const live_selector_names[] = {"none", "reddy", "static", "feedback", "fs", "mb"};
static int selector_index(enum frm_selector sel)
{
    int k = 0;
    while (k < 5 && live_selectors[k] != sel)
        ++k;
    return k;
}
static void next_selector(struct frm_session *s, int started_mb)
{
    int n = started_mb ? 6 : 5, k = (selector_index(s->select.selector) + 1) % n;
    s->select.selector = s->selector = live_selectors[k];
    fprintf(stderr, "hmdlod: selector %s\n", live_selector_names[k]);
}

/* Keys (docs/live.md): Esc or Q quits; S switches the selector; + and − change the budget by 1 ms;
 * V and E toggle the velocity and eccentricity terms; G switches the gaze model between vor and
 * head; C captures a PNG; R starts or stops recording the head trace; arrows look (desk). */
static int handle_keys(struct live_state *st, double dt_s)
{
    int key;
    double look_yaw = 0.0, look_pitch = 0.0; /* this frame's turn from keys and mouse, applied once */
    while (rnd_window_next_key(st->window, &key)) {
        struct frm_session *s = &st->s;
        if (key == RND_KEY_ESCAPE || key == 'Q')
            return 1;
        if (key == '+' || key == '-') {
            double b = s->select.budget_ms + (key == '+' ? 1.0 : -1.0);
            s->select.budget_ms = fmin(1000.0, fmax(1.0, b));
            fprintf(stderr, "hmdlod: budget %.1f ms\n", s->select.budget_ms);
        } else if (key == 'V') {
            s->limits.use_velocity = !s->limits.use_velocity;
            fprintf(stderr, "hmdlod: velocity term %s\n", s->limits.use_velocity ? "on" : "off");
        } else if (key == 'E') {
            s->limits.use_eccentricity = !s->limits.use_eccentricity;
            fprintf(stderr, "hmdlod: eccentricity term %s\n", s->limits.use_eccentricity ? "on" : "off");
        } else if (key == 'S') {
            next_selector(s, st->started_mb);
        } else if (key == 'R') {
            struct hl_error rerr;
            if (!st->record.f && trace_open(&st->record, "hmdlod-live-head.csv", &rerr) != 0)
                fprintf(stderr, "hmdlod: %s\n", rerr.msg);
            else if (st->record.f) {
                st->record.paused = !st->record.paused;
                fprintf(stderr, "hmdlod: head trace %s (%s)\n", st->record.paused ? "paused" : "recording",
                        st->record.path);
            }
        } else if (key == 'G') {
            s->gaze = s->gaze == ACU_GAZE_VOR ? ACU_GAZE_HEAD : ACU_GAZE_VOR;
            fprintf(stderr, "hmdlod: gaze model %s\n", acu_gaze_model_name(s->gaze));
        } else if (key == 'C') {
            st->want_capture = 1;
        } else if (st->is_desk && key >= RND_KEY_UP && key <= RND_KEY_RIGHT) {
            double step = 5.0 * HL_RAD_PER_DEG;
            look_yaw += key == RND_KEY_LEFT ? step : key == RND_KEY_RIGHT ? -step : 0.0;
            look_pitch += key == RND_KEY_UP ? step : key == RND_KEY_DOWN ? -step : 0.0;
        }
    }
    if (st->is_desk) {
        double dx, dy;
        rnd_window_mouse_delta(st->window, &dx, &dy);
        /* 0.17°/px; called every frame so that the look's angular velocity drops to 0 when it stops */
        liv_desk_source_look(st->s.source, look_yaw - dx * 0.003, look_pitch - dy * 0.003, dt_s);
    }
    return 0;
}

/* Tracker health: a loss holds the pose (the source does) and is said in the title and on the
 * terminal; the return is said too. */
static void check_health(struct live_state *st, struct liv_summary *sum, char *why, size_t why_size)
{
    why[0] = '\0';
    if (st->is_desk || !st->s.source->health)
        return;
    enum trk_health h = st->s.source->health(st->s.source, why, why_size);
    if (h != TRK_HEALTH_OK && !st->tracker_lost) {
        st->tracker_lost = 1;
        if (st->tracker_seen_ok)
            sum->tracker_losses++;
        fprintf(stderr, "hmdlod: tracker %s (%s): holding the last pose\n", st->tracker_seen_ok ? "lost" : "not streaming yet",
                why[0] ? why : "no reports");
    } else if (h == TRK_HEALTH_OK && (st->tracker_lost || !st->tracker_seen_ok)) {
        if (st->tracker_seen_ok)
            sum->tracker_resumes++;
        fprintf(stderr, "hmdlod: tracker %s\n", st->tracker_seen_ok ? "back: tracking resumed" : "streaming");
        st->tracker_lost = 0;
        st->tracker_seen_ok = 1;
    }
}

static void status_line(struct live_state *st, const struct frm_frame_record *rec, double interval_ms, int terminal,
                        int quiet)
{
    char line[256];
    snprintf(line, sizeof line, "hmdlod live: frame %.2f/%.2f ms, optimizer %.0f us, %.0fk tris/eye, head %.0f deg/s, "
                                "present %.2f ms%s",
             rec->frame_ms, st->s.select.budget_ms, rec->select_us, (double)rec->triangles_per_eye * 1e-3,
             rec->head_speed_degps, interval_ms, st->tracker_lost ? ", TRACKER LOST: pose held" : "");
    rnd_window_set_title(st->window, line);
    if (terminal && !quiet)
        fprintf(stderr, "%s\n", line);
}

static int run_loop(struct live_state *st, const struct liv_options *o, double rate_hz, struct liv_summary *sum,
                    struct hl_error *err)
{
    struct frm_session *s = &st->s;
    struct liv_pacer pacer;
    sum->self_paced = !swap_throttles(st->window, 1000.0 / rate_hz);
    if (sum->self_paced)
        rnd_window_set_swap_interval(st->window, 0); /* it did not throttle: nothing to gain, only jitter */
    liv_pacer_init(&pacer, rate_hz, sum->self_paced, hl_clock_now_ns());
    int64_t last_status_ns = hl_clock_now_ns();
    int prev_on_time = 1;
    int64_t last_work_ns = 0; /* the previous frame's work (start to ready to swap): the next one's estimate */
    char why[256];
    for (long f = 0; o->frames == 0 || f < o->frames; ++f) {
        rnd_window_poll(st->window);
        if (handle_keys(st, 1.0 / rate_hz) || rnd_window_should_close(st->window) || live_interrupted)
            break;
        check_health(st, sum, why, sizeof why);
        int64_t start_ns = hl_clock_now_ns();
        long missed_before = pacer.missed;
        liv_pacer_plan(&pacer, last_work_ns);
        double display_s = (double)liv_pacer_due_ns(&pacer) * 1e-9;
        struct frm_frame_record rec;
        if (frm_frame_run(s, f, display_s, &rec, err) != 0)
            return -1;
        int64_t t0 = hl_clock_now_ns();
        if (rnd_distortion_draw(st->distortion, 1, err) != 0)
            return -1;
        double dist_ms = (double)(hl_clock_now_ns() - t0) * 1e-6;
        if (st->want_capture) {
            char path[600];
            snprintf(path, sizeof path, "hmdlod-capture-%06ld.png", f);
            if (capture_write(st->window, path, err) != 0)
                return -1;
            fprintf(stderr, "hmdlod: captured %s\n", path);
            st->want_capture = 0;
        }
        last_work_ns = hl_clock_now_ns() - start_ns;
        liv_pacer_wait(&pacer);
        rnd_window_swap(st->window);
        int64_t present_ns = hl_clock_now_ns();
        double interval_ms = liv_pacer_presented(&pacer, present_ns);
        /* Frame-to-present: from the frame's start (its pose asked for) to the swap's return; the
         * display adds its scan-out, which no API here reports. */
        double to_present_ms = (double)(present_ns - start_ns) * 1e-6;
        struct trk_pose pose;
        if (st->record.f && trk_source_pose_at(s->source, display_s, &pose, err) == 0)
            liv_record_row(&st->record, &pose);
        if (liv_record_end_row(&st->record, err) != 0)
            return -1;
        int on_time = pacer.missed == missed_before;
        if (st->log.f) {
            if (st->log.t0_s < 0)
                st->log.t0_s = display_s;
            fprintf(st->log.f, "%ld,%.6f,%.4f,%.4f,%.4f,%.4f,%ld,%d,%llu,%.3f,%d\n", f, display_s - st->log.t0_s,
                    rec.frame_ms, dist_ms, interval_ms, to_present_ms, pacer.missed, on_time,
                    (unsigned long long)rec.triangles_per_eye, rec.head_speed_degps, !st->tracker_lost);
            st->log.rows++;
            if (liv_record_end_row(&st->log, err) != 0)
                return -1;
        }
        if ((f > 0 && on_time && prev_on_time && liv_series_push(&st->on_time_ms, interval_ms) != 0) ||
            (f > 0 && liv_series_push(&st->present_ms, interval_ms) != 0) || liv_series_push(&st->frame_ms, rec.frame_ms) != 0 ||
            liv_series_push(&st->distortion_ms, dist_ms) != 0 || liv_series_push(&st->to_present_ms, to_present_ms) != 0)
            return hl_fail(err, "live: out of memory for frame times");
        prev_on_time = on_time;
        st->triangles_sum += (double)rec.triangles_per_eye;
        st->optimizer_sum += rec.select_us;
        sum->deadlines_met += rec.frame_ms + dist_ms <= s->select.budget_ms;
        sum->frames = f + 1;
        int64_t now = hl_clock_now_ns();
        if (now - last_status_ns >= 1000000000 || f == 0) {
            status_line(st, &rec, interval_ms, f > 0, o->quiet_status);
            last_status_ns = now;
        }
    }
    sum->missed_frames = pacer.missed;
    if (pacer.clock_jumps > 0)
        fprintf(stderr, "hmdlod: the frame clock jumped or stalled by more than 1 s %ld times: pacing re-anchored, "
                        "those presents not counted as intervals\n", pacer.clock_jumps);
    return 0;
}

static void finish_summary(struct live_state *st, double rate_hz, struct liv_summary *sum)
{
    sum->rate_hz = rate_hz;
    sum->period_ms = 1000.0 / rate_hz;
    sum->budget_ms = st->s.select.budget_ms;
    /* As the keys left them (S, V, E, G). */
    snprintf(sum->selector, sizeof sum->selector, "%s", live_selector_names[selector_index(st->s.select.selector)]);
    snprintf(sum->gaze, sizeof sum->gaze, "%s", acu_gaze_model_name(st->s.gaze));
    sum->velocity_term = st->s.limits.use_velocity;
    sum->eccentricity_term = st->s.limits.use_eccentricity;
    liv_series_stats(&st->present_ms, NULL, &sum->present_stddev_ms, &sum->present_median_ms, &sum->present_p99_ms,
                 &sum->present_max_ms);
    liv_series_stats(&st->frame_ms, &sum->frame_mean_ms, NULL, NULL, &sum->frame_p99_ms, NULL);
    liv_series_stats(&st->distortion_ms, &sum->distortion_mean_ms, NULL, NULL, &sum->distortion_p99_ms, NULL);
    liv_series_stats(&st->on_time_ms, NULL, &sum->on_time_stddev_ms, &sum->on_time_median_ms, &sum->on_time_p99_ms, NULL);
    sum->on_time_intervals = st->on_time_ms.n;
    liv_series_stats(&st->to_present_ms, &sum->to_present_mean_ms, NULL, NULL, &sum->to_present_p99_ms, NULL);
    if (sum->frames > 0) {
        sum->triangles_mean = st->triangles_sum / (double)sum->frames;
        sum->optimizer_us_mean = st->optimizer_sum / (double)sum->frames;
    }
    rnd_window_size(st->window, &sum->window_w, &sum->window_h);
    sum->has_lens = rnd_distortion_has_lens(st->distortion);
    snprintf(sum->display, sizeof sum->display, "%s", st->s.display.name);
    snprintf(sum->renderer, sizeof sum->renderer, "%s", rnd_renderer_name(st->s.renderer));
    snprintf(sum->pacing, sizeof sum->pacing, "%s",
             sum->self_paced ? "self-paced on the monotonic clock (swap interval 1 does not throttle here)"
                             : "swap interval 1 (the display throttles)");
}

int liv_run(const struct liv_options *o, struct liv_summary *sum, struct hl_error *err)
{
    memset(sum, 0, sizeof *sum);
    struct live_state st;
    memset(&st, 0, sizeof st);
    int rc = -1;
    const struct frm_options *so = o->session;
    struct hmd_profile display;
    struct frm_session_made made = {NULL, NULL};
    if (!so || frm_options_check(so, &st.s.selector, &st.s.reading, err) != 0)
        return so ? -1 : hl_fail(err, "live: no session options");
    if (o->frames < 0)
        return hl_fail(err, "--frames: %ld must be >= 0", o->frames);
    if (hmd_profile_load(so->display, &display, err) != 0)
        return -1;
    double rate_hz = o->rate_hz > 0.0 ? o->rate_hz : display.refresh_hz;

    struct rnd_window_params wp = {"hmdlod live", 0, 0, o->monitor};
    if (o->window_w_px > 0 && o->window_h_px > 0)
        wp.width_px = o->window_w_px & ~1, wp.height_px = o->window_h_px;
    else
        window_size(&display, &wp.width_px, &wp.height_px);
    if (rnd_window_create(&wp, &st.window, err) != 0)
        return -1;
    int eye_w = (int)lround(display.eye_width_px * so->render_scale);
    int eye_h = (int)lround(display.eye_height_px * so->render_scale);
    if (rnd_renderer_create_in_window(st.window, eye_w > 0 ? eye_w : 1, eye_h > 0 ? eye_h : 1, &made.renderer, err) !=
            0 ||
        open_source(o, &made.source, &st.is_desk, err) != 0) {
        rnd_renderer_destroy(made.renderer);
        goto done;
    }
    snprintf(sum->source, sizeof sum->source, "%s", made.source->name);
    if (frm_session_open(&st.s, so, &made, err) != 0)
        goto done;
    int ww, wh;
    rnd_window_size(st.window, &ww, &wh);
    st.s.composite_in_distortion = 1; /* the distortion pass composites foveated layers (render/window.h) */
    if (rnd_distortion_create(st.s.renderer, &st.s.display, ww, wh, 0, &st.distortion, err) != 0 ||
        trace_open(&st.record, o->record_path, err) != 0 ||
        liv_record_open(&st.log, o->log_path,
                         "frame,t_s,frame_ms,distortion_ms,present_interval_ms,start_to_present_ms,missed_total,"
                         "on_time,triangles_per_eye,head_degps,tracking\n", err) != 0)
        goto done;
    if (o->record_path && !st.is_desk) {
        raw_path_of(o->record_path, sum->raw_record, sizeof sum->raw_record);
        if (trk_tracker_source_record(st.s.source, sum->raw_record, err) != 0)
            goto done;
    }
    snprintf(sum->scene, sizeof sum->scene, "%s", so->scene);
    snprintf(sum->selector, sizeof sum->selector, "%s", so->selector);
    st.started_mb = st.s.selector == FRM_SELECT_MB;

    struct sigaction sa, old_int, old_term;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = live_on_signal;
    sigemptyset(&sa.sa_mask);
    live_interrupted = 0;
    sigaction(SIGINT, &sa, &old_int);
    sigaction(SIGTERM, &sa, &old_term);
    int loop = run_loop(&st, o, rate_hz, sum, err);
    sigaction(SIGINT, &old_int, NULL);
    sigaction(SIGTERM, &old_term, NULL);
    if (loop != 0)
        goto done;
    if (live_interrupted)
        fprintf(stderr, "hmdlod: interrupted: finishing the session\n");
    finish_summary(&st, rate_hz, sum);
    if (st.record.dropped_rows > 0)
        fprintf(stderr, "hmdlod: --record %s: %ld rows dropped: their pose time did not move forward\n",
                st.record.path, st.record.dropped_rows);
    if (liv_record_commit(&st.record, err) != 0 || liv_record_commit(&st.log, err) != 0 ||
        (sum->raw_record[0] && trk_tracker_source_record(st.s.source, NULL, err) != 0))
        goto done;
    if (sum->raw_record[0]) {
        struct trk_tracker_stats ts;
        if (trk_tracker_source_stats(st.s.source, &ts) == 0)
            sum->raw_reports = (long)ts.recorded;
    }
    if (o->capture_path && sum->frames > 0) {
        /* The FBO still holds the last frame: draw it once more to the back buffer and read that. */
        if (rnd_distortion_draw(st.distortion, 1, err) != 0 || capture_write(st.window, o->capture_path, err) != 0)
            goto done;
        snprintf(sum->capture, sizeof sum->capture, "%s", o->capture_path);
    }
    rc = 0;
done:
    liv_record_abort(&st.record);
    liv_record_abort(&st.log);
    liv_series_free(&st.present_ms);
    liv_series_free(&st.frame_ms);
    liv_series_free(&st.distortion_ms);
    liv_series_free(&st.to_present_ms);
    liv_series_free(&st.on_time_ms);
    rnd_distortion_destroy(st.distortion);
    frm_session_close(&st.s); /* the renderer before the window it draws in */
    rnd_window_destroy(st.window);
    return rc;
}

void liv_summary_print(FILE *f, const struct liv_summary *s)
{
    fprintf(f, "live session: %s on %s, scene %s, selector %s, pose source %s\n", s->display, s->renderer, s->scene,
            s->selector, s->source);
    fprintf(f, "  window %d x %d, distortion pass %s\n", s->window_w, s->window_h,
            s->has_lens ? "with the profile's lens and aberration" : "undistorted (the profile has no lens coefficients)");
    fprintf(f, "  model: gaze %s, velocity term %s, eccentricity term %s\n", s->gaze, s->velocity_term ? "on" : "off",
            s->eccentricity_term ? "on" : "off");
    fprintf(f, "  pacing: %.6g Hz (%.3f ms), %s\n", s->rate_hz, s->period_ms, s->pacing);
    fprintf(f, "  frames %ld, missed %ld (refresh slots without a new frame), within budget %ld\n", s->frames,
            s->missed_frames, s->deadlines_met);
    fprintf(f, "  present interval ms: median %.3f  p99 %.3f  stddev %.3f  max %.3f\n", s->present_median_ms,
            s->present_p99_ms, s->present_stddev_ms, s->present_max_ms);
    fprintf(f, "  between frames that made their slots (%ld): median %.3f  p99 %.3f  stddev %.3f\n", s->on_time_intervals,
            s->on_time_median_ms, s->on_time_p99_ms, s->on_time_stddev_ms);
    fprintf(f, "  frame ms: mean %.3f  p99 %.3f (budget %.3f); distortion pass ms: mean %.3f  p99 %.3f\n",
            s->frame_mean_ms, s->frame_p99_ms, s->budget_ms, s->distortion_mean_ms, s->distortion_p99_ms);
    fprintf(f, "  frame start to present ms: mean %.3f  p99 %.3f (pose predicted to the slot's time)\n",
            s->to_present_mean_ms, s->to_present_p99_ms);
    fprintf(f, "  triangles per eye: mean %.0f; optimizer us: mean %.1f\n", s->triangles_mean, s->optimizer_us_mean);
    if (s->tracker_losses || s->tracker_resumes)
        fprintf(f, "  tracker: lost %ld times, resumed %ld times\n", s->tracker_losses, s->tracker_resumes);
    if (s->capture[0])
        fprintf(f, "  capture: %s\n", s->capture);
    if (s->raw_record[0])
        fprintf(f, "  raw recording: %s (%ld reports)\n", s->raw_record, s->raw_reports);
}
