/* Little-endian fields of the binary formats (.lod, tracker recordings, .glb headers), byte by byte
 * so that neither the host's byte order nor the buffer's alignment matters. */
#include <string.h>

#include "base/base.h"

void hl_le_put_u16(unsigned char *p, uint16_t v) { p[0] = (unsigned char)v, p[1] = (unsigned char)(v >> 8); }

void hl_le_put_u32(unsigned char *p, uint32_t v)
{
    for (int i = 0; i < 4; ++i)
        p[i] = (unsigned char)(v >> (8 * i));
}

void hl_le_put_u64(unsigned char *p, uint64_t v)
{
    for (int i = 0; i < 8; ++i)
        p[i] = (unsigned char)(v >> (8 * i));
}

void hl_le_put_f32(unsigned char *p, float f)
{
    uint32_t v;
    memcpy(&v, &f, 4);
    hl_le_put_u32(p, v);
}

void hl_le_put_f64(unsigned char *p, double d)
{
    uint64_t v;
    memcpy(&v, &d, 8);
    hl_le_put_u64(p, v);
}

uint16_t hl_le_get_u16(const unsigned char *p) { return (uint16_t)(p[0] | p[1] << 8); }

uint32_t hl_le_get_u32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

uint64_t hl_le_get_u64(const unsigned char *p) { return (uint64_t)hl_le_get_u32(p) | (uint64_t)hl_le_get_u32(p + 4) << 32; }

float hl_le_get_f32(const unsigned char *p)
{
    uint32_t v = hl_le_get_u32(p);
    float f;
    memcpy(&f, &v, 4);
    return f;
}

double hl_le_get_f64(const unsigned char *p)
{
    uint64_t v = hl_le_get_u64(p);
    double d;
    memcpy(&d, &v, 8);
    return d;
}
