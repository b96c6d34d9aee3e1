/* hmdlod: perceptual level of detail for head-mounted displays. Dispatches to one function per
 * subcommand (app/commands.h); everything else lives in the modules. */
#include <errno.h>
#include <malloc.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/base.h"

#include "app/commands.h"

struct command {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *summary;
};

static const struct command commands[] = {
    {"demo", cmd_demo, "replay a built-in head-motion clip through a built-in scene (no files needed)"},
    {"display", cmd_display, "list built-in display profiles, or show one's pixels, FOV, xi and thresholds"},
    {"acuity", cmd_acuity, "evaluate Reddy's acuity model H(v, E) and min(H, xi)"},
    {"replay", cmd_replay, "replay a head-motion trace through a scene, writing per-frame CSV, summary, PNGs"},
    {"live", cmd_live, "live session: a window or a headset's output, lens distortion, tracker or mouse look"},
    {"bench", cmd_bench, "measure and print figures with their context (bench tracking: tracker accuracy, speed)"},
    {"record", cmd_record, "record a head tracker's raw reports (with host times, CRC) to a raw recording"},
    {"convert", cmd_convert, "convert a raw recording into a head-motion trace CSV (same parser and fusion)"},
    {"lodgen", cmd_lodgen, "import a mesh (OBJ/PLY/OFF/STL/glTF), decimate it into an LOD chain, write a .lod file"},
    {"analyze", cmd_analyze, "Reddy's offline spatial-frequency analysis of a .lod file (image-based frequency tables)"},
    {"calibrate", cmd_calibrate, "measure this machine's rendering cost, fit the cost model, write a cost profile"},
    {"devices", cmd_devices, "list the supported head trackers present, whether they can be opened, and why not"},
};

static void print_usage(FILE *f)
{
    fprintf(f, "usage: hmdlod <command> [options]   (hmdlod <command> --help for its options)\n\n"
               "hmdlod renders both eyes of a head-mounted display with a level of detail that follows\n"
               "Reddy's visual acuity model: what the viewer cannot resolve is not drawn.\n\n"
               "  --max-input-bytes N  (before the command) read input files of up to N bytes (default 1 GiB;\n"
               "                       the same as the environment variable " HL_FILE_MAX_BYTES_ENV ")\n\ncommands:\n");
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; ++i)
        fprintf(f, "  %-9s %s\n", commands[i].name, commands[i].summary);
}

/* --max-input-bytes N before the command: the input size limit of base/file.c for this run and for
 * the replays it starts, passed on through the environment variable every loader reads. */
static int set_max_input_bytes(const char *text)
{
    char *end = NULL;
    errno = 0;
    unsigned long long n = text ? strtoull(text, &end, 10) : 0;
    if (!text || errno != 0 || end == text || *end != '\0' || n == 0 || text[0] == '-') {
        fprintf(stderr, "hmdlod: --max-input-bytes: '%s' is not a positive byte count\n", text ? text : "");
        return -1;
    }
    if (setenv(HL_FILE_MAX_BYTES_ENV, text, 1) != 0) {
        fprintf(stderr, "hmdlod: --max-input-bytes: %s\n", strerror(errno));
        return -1;
    }
    return 0;
}

/* The allocator keeps what a frame frees. Mesa's llvmpipe allocates its scene bins in 64 KiB blocks
 * on the main thread and frees them after every frame; with glibc's defaults the free top of the heap
 * (over 128 KiB) goes back to the kernel at once, and the next frame faults the same pages in again:
 * about 5000 fresh pages a frame, twice the frame time of a standalone replay, and the first session
 * of a process paying for the next (docs/replay-output.md "minor_faults"). So the heap is trimmed only
 * by an explicit malloc_trim (the live pacer's idle trim), and blocks up to 32 MiB (glibc's highest
 * mmap threshold on 64 bits) come from the heap instead of a fresh mapping each time. Setting either
 * value also turns off glibc's dynamic threshold, so these hold for the whole run. */
static void tune_allocator(void)
{
    mallopt(M_TRIM_THRESHOLD, 512 * 1024 * 1024);
    mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
}

int main(int argc, char **argv)
{
    tune_allocator();
    if (argc >= 2 && !strcmp(argv[1], "--max-input-bytes")) {
        if (set_max_input_bytes(argc >= 3 ? argv[2] : NULL) != 0)
            return 1;
        argv[2] = argv[0];
        argc -= 2, argv += 2;
    }
    if (argc < 2) {
        print_usage(stderr);
        return 1;
    }
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || !strcmp(argv[1], "help")) {
        print_usage(stdout);
        return 0;
    }
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; ++i)
        if (!strcmp(argv[1], commands[i].name))
            return commands[i].run(argc - 1, argv + 1);
    fprintf(stderr, "hmdlod: unknown command '%s' (try: hmdlod --help)\n", argv[1]);
    return 1;
}
