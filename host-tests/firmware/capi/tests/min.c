/* The smallest C firmware images of the C API, one kernel each through its own entry point (so
 * nothing else is linked), inputs behind volatile so nothing is folded. Built by ../test.sh for
 * Cortex-M with cortex_m.c, in three variants; their .text is the table in the README:
 *   (default)           vs_int_sample_u8_opacity_weighted_trilinear: one integer sample
 *   -DVS_MIN_CAST       vs_cast_u8_opacity_weighted_trilinear: one float ray, front to back
 *   -DVS_MIN_DISPATCH   vs_cast_u8: the same ray through the dispatching entry point */
#include <stdint.h>
#include <stddef.h>
#include "volsample.h"

static volatile uint8_t voxels[8] = {255, 255, 255, 255, 255, 0, 0, 0};
static volatile uint32_t where[3] = {128, 0, 0};
static volatile float ray[6] = {3.0f, 0.0f, 0.0f, -1.0f, 0.0f, 0.0f};

int main(void) {
    uint8_t v[8];
    for (int i = 0; i < 8; i++) v[i] = voxels[i];
    const VsVolumeU8 vol = {v, 2, 2, 1, 1};
#if defined(VS_MIN_CAST) || defined(VS_MIN_DISPATCH)
    float o[3], d[3];
    for (int i = 0; i < 3; i++) {
        o[i] = ray[i];
        d[i] = ray[3 + i];
    }
    const VsMarch m = {VS_MODE_OPACITY_WEIGHTED, VS_FILTER_TRILINEAR, VS_ORDER_FRONT_TO_BACK, 1.0f, 0.0f, 1.0f};
    VsSample s;
#if defined(VS_MIN_CAST)
    int32_t st = vs_cast_u8_opacity_weighted_trilinear(&vol, &m, o, d, &s);
#else
    int32_t st = vs_cast_u8(&vol, &m, o, d, &s);
#endif
    /* Through the opaque white voxel: exactly opaque white. */
    return !(st == VS_OK && s.a == 1.0f && s.c[0] == 1.0f && s.c[1] == 1.0f && s.c[2] == 1.0f);
#else
    uint32_t p[3];
    for (int i = 0; i < 3; i++) p[i] = where[i];
    VsIntSample s;
    /* Wittenbrink's pair at x = 0.5: white, half opaque (32640 each). */
    return !(vs_int_sample_u8_opacity_weighted_trilinear(&vol, p, &s) == VS_OK && s.a == 32640 &&
             s.c[0] == 32640 && s.c[1] == 32640 && s.c[2] == 32640);
#endif
}
