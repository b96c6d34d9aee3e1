/* hmdlod: perceptual level of detail for head-mounted displays. Dispatches to one function per
 * subcommand (app/commands.h); everything else lives in the modules. */
#include <stdio.h>
#include <string.h>

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
               "Reddy's visual acuity model: what the viewer cannot resolve is not drawn.\n\ncommands:\n");
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; ++i)
        fprintf(f, "  %-9s %s\n", commands[i].name, commands[i].summary);
}

int main(int argc, char **argv)
{
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
