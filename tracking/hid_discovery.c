/* Discovery of supported trackers through hidapi (hidraw backend): match each HID interface against
 * trk_device_table (DEVICES.md §2a) and try to open it, so `hmdlod devices` and the live source can
 * say *why* a present headset cannot be used (DEVICES.md §3: users see "got -1 bytes" or a bare
 * failure; we name the node, the errno and the fix). */
#define _DEFAULT_SOURCE /* realpath() for the /proc holder scan */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <linux/hidraw.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <hidapi.h>

#include "tracking/hid_internal.h"

static pthread_once_t lib_once = PTHREAD_ONCE_INIT;
static int lib_status = -1;

static void lib_init_once(void) { lib_status = hid_init(); }

int trk_hid_lib_init(struct hl_error *err)
{
    pthread_once(&lib_once, lib_init_once);
    if (lib_status != 0)
        return hl_fail(err, "hidapi: hid_init failed (hidraw backend: is udev available?)");
    return 0;
}

void trk_hid_wide_to_utf8(const wchar_t *w, char *out, size_t size)
{
    size_t n = 0;
    if (size == 0)
        return;
    for (; w && *w; ++w) {
        uint32_t c = (uint32_t)*w;
        uint8_t b[4];
        size_t k;
        if (c < 0x80) {
            b[0] = (uint8_t)c;
            k = 1;
        } else if (c < 0x800) {
            b[0] = (uint8_t)(0xC0 | (c >> 6));
            b[1] = (uint8_t)(0x80 | (c & 0x3F));
            k = 2;
        } else if (c < 0x10000) {
            if (c >= 0xD800 && c < 0xE000)
                c = 0xFFFD; /* lone surrogate: not a character */
            b[0] = (uint8_t)(0xE0 | (c >> 12));
            b[1] = (uint8_t)(0x80 | ((c >> 6) & 0x3F));
            b[2] = (uint8_t)(0x80 | (c & 0x3F));
            k = 3;
        } else if (c < 0x110000) {
            b[0] = (uint8_t)(0xF0 | (c >> 18));
            b[1] = (uint8_t)(0x80 | ((c >> 12) & 0x3F));
            b[2] = (uint8_t)(0x80 | ((c >> 6) & 0x3F));
            b[3] = (uint8_t)(0x80 | (c & 0x3F));
            k = 4;
        } else {
            b[0] = '?';
            k = 1;
        }
        if (n + k >= size)
            break; /* never cut a character in half */
        memcpy(out + n, b, k);
        n += k;
    }
    out[n] = '\0';
}

const struct trk_device_info *trk_hid_match(uint16_t vid, uint16_t pid, int interface_number,
                                            const char *manufacturer)
{
    for (size_t i = 0; i < trk_device_table_count; ++i) {
        const struct trk_device_info *d = &trk_device_table[i];
        if (d->vid != vid || d->pid != pid)
            continue;
        if (d->interface_number >= 0 && d->interface_number != interface_number)
            continue;
        if (d->manufacturer && (!manufacturer || strcmp(manufacturer, d->manufacturer) != 0))
            continue;
        return d;
    }
    return NULL;
}

/* Processes holding `path` open, from /proc/<pid>/fd (only those this user may inspect), written as
 * " (held by pid 123 vrserver, pid 456 …)". Empty when none are visible. */
static void find_holders(const char *path, char *out, size_t size)
{
    out[0] = '\0';
    char want[PATH_MAX];
    if (!realpath(path, want))
        return;
    DIR *proc = opendir("/proc");
    if (!proc)
        return;
    size_t used = 0;
    int found = 0;
    pid_t self = getpid();
    struct dirent *pe;
    while ((pe = readdir(proc)) != NULL && found < 4) {
        char *end;
        long pid = strtol(pe->d_name, &end, 10);
        if (*end != '\0' || pid <= 0 || pid == (long)self)
            continue;
        char fddir[64];
        snprintf(fddir, sizeof fddir, "/proc/%ld/fd", pid);
        DIR *fds = opendir(fddir);
        if (!fds)
            continue;
        struct dirent *fe;
        int holds = 0;
        while (!holds && (fe = readdir(fds)) != NULL) {
            char link[96], target[PATH_MAX];
            if (fe->d_name[0] == '.')
                continue;
            snprintf(link, sizeof link, "%s/%.20s", fddir, fe->d_name);
            ssize_t n = readlink(link, target, sizeof target - 1);
            if (n <= 0)
                continue;
            target[n] = '\0';
            holds = strcmp(target, want) == 0;
        }
        closedir(fds);
        if (!holds)
            continue;
        char comm[64] = "?", commpath[64];
        snprintf(commpath, sizeof commpath, "/proc/%ld/comm", pid);
        FILE *f = fopen(commpath, "r");
        if (f) {
            if (fgets(comm, sizeof comm, f))
                comm[strcspn(comm, "\n")] = '\0';
            fclose(f);
        }
        int w = snprintf(out + used, size - used, "%s pid %ld %s", found ? "," : " (held by", pid, comm);
        if (w < 0 || (size_t)w >= size - used)
            break;
        used += (size_t)w;
        ++found;
    }
    closedir(proc);
    if (found && used + 2 <= size)
        strcat(out, ")");
    else if (!found)
        out[0] = '\0';
}

int trk_hid_probe_node(const char *path, char *why, size_t why_size)
{
    int fd = open(path, O_RDWR | O_CLOEXEC);
    if (fd < 0) {
        int e = errno;
        char holders[160];
        switch (e) {
        case EACCES:
        case EPERM:
            /* DEVICES.md §3: the uaccess tag gives the seat user an ACL; without the rule the node is
             * root-only. Rules apply only after reload + trigger (thaytan/OpenHMD #42) and a replug. */
            snprintf(why, why_size,
                     "cannot open %s read-write: %s. Install the udev rules: sudo scripts/install-udev-rules.sh "
                     "(copies scripts/70-hmdlod.rules to /etc/udev/rules.d, then udevadm control --reload-rules "
                     "and udevadm trigger), then replug the headset",
                     path, strerror(e));
            break;
        case EBUSY:
            find_holders(path, holders, sizeof holders);
            snprintf(why, why_size,
                     "cannot open %s: %s: another process holds it%s; quit it (SteamVR, another OpenXR runtime, "
                     "a keep-awake tool) and retry",
                     path, strerror(e), holders[0] ? holders : "");
            break;
        case ENOENT:
        case ENODEV:
        case ENXIO:
            snprintf(why, why_size, "cannot open %s: %s: the device went away (unplugged?)", path, strerror(e));
            break;
        default:
            snprintf(why, why_size, "cannot open %s: %s", path, strerror(e));
            break;
        }
        return -1;
    }
    int desc_size = 0;
    if (ioctl(fd, HIDIOCGRDESCSIZE, &desc_size) < 0) {
        int e = errno;
        close(fd);
        snprintf(why, why_size,
                 "%s opens, but its report-descriptor ioctl (HIDIOCGRDESCSIZE) fails: %s: not a working hidraw "
                 "node (HID driver unbound, or a stale node)",
                 path, strerror(e));
        return -1;
    }
    close(fd);
    return 0;
}

const char *trk_hid_supported_list(char *buf, size_t size)
{
    size_t used = 0;
    if (size == 0)
        return buf;
    buf[0] = '\0';
    for (size_t i = 0; i < trk_device_table_count; ++i) {
        const struct trk_device_info *d = &trk_device_table[i];
        if (d->role != TRK_ROLE_IMU)
            continue;
        int w = snprintf(buf + used, size - used, "%s%s %04x:%04x", used ? ", " : "", d->name, d->vid, d->pid);
        if (w < 0 || (size_t)w >= size - used)
            break;
        used += (size_t)w;
    }
    return buf;
}

int trk_hid_enumerate(struct trk_hid_device_desc *out, int max, struct hl_error *err)
{
    if (trk_hid_lib_init(err) != 0)
        return -1;
    /* hid_enumerate returns NULL both for "nothing" and for failure; with udev working, an empty
     * list is the honest reading. */
    struct hid_device_info *list = hid_enumerate(0, 0);
    int n = 0;
    for (struct hid_device_info *i = list; i && n < max; i = i->next) {
        if (!i->path)
            continue;
        char manufacturer[TRK_HID_STRING_SIZE];
        trk_hid_wide_to_utf8(i->manufacturer_string, manufacturer, sizeof manufacturer);
        const struct trk_device_info *info =
            trk_hid_match(i->vendor_id, i->product_id, i->interface_number, manufacturer);
        if (!info)
            continue;
        /* hidapi ≥ 0.13 lists a node once per top-level usage: keep the first. */
        int dup = 0;
        for (int k = 0; k < n && !dup; ++k)
            dup = strcmp(out[k].path, i->path) == 0;
        if (dup)
            continue;
        struct trk_hid_device_desc *d = &out[n++];
        memset(d, 0, sizeof *d);
        snprintf(d->path, sizeof d->path, "%s", i->path);
        d->info = info;
        d->vid = i->vendor_id;
        d->pid = i->product_id;
        d->interface_number = i->interface_number;
        memcpy(d->manufacturer, manufacturer, sizeof d->manufacturer);
        trk_hid_wide_to_utf8(i->product_string, d->product, sizeof d->product);
        trk_hid_wide_to_utf8(i->serial_number, d->serial, sizeof d->serial);
        d->can_open = trk_hid_probe_node(d->path, d->why, sizeof d->why) == 0;
    }
    hid_free_enumeration(list);
    return n;
}
