/* PNG capture. Written through hl_out (base.h): a temporary file in the destination folder renamed into
 * place, so a reader (or a crash) never sees half a PNG and a planted symlink is replaced, not followed. */
#include "render/render_internal.h"

#include <errno.h>
#include <png.h>
#include <setjmp.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

struct rnd_png_state {
    char reason[256];
};

static void rnd_png_on_error(png_structp png, png_const_charp msg)
{
    struct rnd_png_state *st = png_get_error_ptr(png);
    snprintf(st->reason, sizeof st->reason, "libpng: %s", msg);
    png_longjmp(png, 1);
}

static void rnd_png_on_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg; /* warnings do not make the file wrong */
}

/* Encodes into an open stream; returns 0 or fills st->reason. Kept apart from the file handling so
 * that setjmp only has to protect libpng's own objects. */
static int rnd_png_encode(FILE *f, const uint8_t *rgba, int w, int h, struct rnd_png_state *st)
{
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, st, rnd_png_on_error, rnd_png_on_warning);
    if (!png) {
        snprintf(st->reason, sizeof st->reason, "out of memory");
        return -1;
    }
    png_infop info = png_create_info_struct(png);
    if (!info) {
        png_destroy_write_struct(&png, NULL);
        snprintf(st->reason, sizeof st->reason, "out of memory");
        return -1;
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return -1;
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, 8, PNG_COLOR_TYPE_RGBA, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, 3); /* captures are frequent; size matters less than speed */
    png_write_info(png, info);
    for (int y = 0; y < h; ++y)
        png_write_row(png, rgba + (size_t)y * (size_t)w * 4);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    return 0;
}

int rnd_png_write(const char *path, const uint8_t *rgba, int width_px, int height_px, struct hl_error *err)
{
    if (!path || !*path)
        return hl_fail(err, "png: empty path");
    if (!rgba || width_px < 1 || height_px < 1 || width_px > 1000000 || height_px > 1000000)
        return hl_fail(err, "%s: bad image (%d×%d)", path, width_px, height_px);
    struct hl_out o;
    if (hl_out_open(&o, path, err) != 0)
        return -1;
    struct rnd_png_state st = {""};
    if (rnd_png_encode(o.f, rgba, width_px, height_px, &st) != 0) {
        if (ferror(o.f)) /* libpng's "Write Error": the commit fails, naming why (a full disk) */
            return hl_out_commit(&o, err) != 0 ? -1 : hl_fail(err, "%s: %s", path, st.reason);
        hl_out_abort(&o);
        return hl_fail(err, "%s: %s", path, st.reason);
    }
    return hl_out_commit(&o, err);
}
