/* C test of the volsample C API: compiled with `gcc -ffreestanding` (only the freestanding
 * headers), linked against the Rust staticlib, checked against known values: Wittenbrink's
 * fig. 4 pair (opacity-weighted stays white, separate bleeds red), exact integer samples,
 * opacity correction's closed form, compositing, the premultiplied-storage rounding, and the
 * error statuses. Exit status 0 only if every check passes. */
#include <stdint.h>
#include <stddef.h>
#include "volsample.h"

/* Output is the one thing a freestanding program lacks; the test binary is linked with the
 * host C library for it (the staticlib itself needs nothing but memcpy/memset). */
int printf(const char *fmt, ...);

static int failures = 0;
static int checks = 0;

static void check(int ok, const char *what) {
    checks++;
    if (!ok) {
        failures++;
        printf("FAIL: %s\n", what);
    }
}

static int near(float x, float want, float tol) {
    float d = x - want;
    return d <= tol && -d <= tol;
}

int main(void) {
    /* Wittenbrink fig. 4: an opaque white voxel next to a transparent red one. */
    const uint8_t pair[8] = {255, 255, 255, 255, 255, 0, 0, 0};
    const VsVolumeU8 vol = {pair, 2, 2, 1, 1};
    const uint32_t mid[3] = {128, 0, 0}; /* x = 0.5 with 8 fractional bits */
    VsIntSample s;

    check(vs_int_sample_u8(&vol, VS_MODE_OPACITY_WEIGHTED, VS_FILTER_TRILINEAR, mid, &s) == VS_OK,
          "int OW sample status");
    check(s.a == VS_INT_ONE / 2 && s.c[0] == VS_INT_ONE / 2 && s.c[1] == VS_INT_ONE / 2 &&
              s.c[2] == VS_INT_ONE / 2,
          "int OW: white, half opaque (32640 each)");
    check(vs_int_sample_u8(&vol, VS_MODE_SEPARATE, VS_FILTER_TRILINEAR, mid, &s) == VS_OK,
          "int separate sample status");
    check(s.a == 32640 && s.c[0] == 32640 && s.c[1] == 16320 && s.c[2] == 16320,
          "int separate: red bleeds in (32640, 16320, 16320)");
    check(vs_int_sample_u8(&vol, VS_MODE_OPACITY_WEIGHTED, VS_FILTER_NEAREST, mid, &s) == VS_OK &&
              s.a == 0 && s.c[0] == 0,
          "int nearest rounds x = 0.5 half up to the transparent voxel");

    /* A float ray along x through the pair, from the red side: the opaque white voxel wins. */
    const VsMarch ow = {VS_MODE_OPACITY_WEIGHTED, VS_FILTER_TRILINEAR, VS_ORDER_FRONT_TO_BACK, 1.0f, 0.0f, 1.0f};
    const float origin[3] = {3.0f, 0.0f, 0.0f}, dir[3] = {-1.0f, 0.0f, 0.0f};
    VsSample px;
    check(vs_cast_u8(&vol, &ow, origin, dir, &px) == VS_OK, "cast status");
    check(px.a == 1.0f && px.c[0] == 1.0f && px.c[1] == 1.0f && px.c[2] == 1.0f,
          "OW ray through the opaque white voxel is exactly opaque white");
    VsMarch sep = ow;
    sep.mode = VS_MODE_SEPARATE;
    sep.filter = VS_FILTER_NEAREST;
    check(vs_cast_u8(&vol, &sep, origin, dir, &px) == VS_OK && px.a == 1.0f && px.c[1] == 1.0f,
          "nearest separate ray sees only the white voxel");

    /* Opacity correction: alpha 0.5 over twice the distance is 0.75; color scales by 1.5. */
    const VsSample half = {{0.5f, 0.25f, 0.0f}, 0.5f};
    VsSample cor = vs_correct(half, 2.0f);
    check(near(cor.a, 0.75f, 1e-6f) && near(cor.c[0], 0.75f, 1e-6f) && near(cor.c[1], 0.375f, 1e-6f) &&
              cor.c[2] == 0.0f,
          "correct(0.5, ratio 2) = 0.75, color x1.5");
    /* Extinction: tau = ln 2 over d = 1 gives alpha 0.5; C = C_tau/tau * alpha. */
    VsSample ex = vs_integrate_step(0.69314718f, 0.0f, 0.0f, 0.69314718f, 1.0f);
    check(near(ex.a, 0.5f, 1e-6f) && near(ex.c[0], 0.5f, 1e-6f), "integrate_step(tau = ln 2) = 0.5");

    /* Integer compositing: two half-opaque white samples give 3/4. */
    const VsIntSample two[2] = {{{32640, 32640, 32640}, 32640}, {{32640, 32640, 32640}, 32640}};
    size_t used = 0;
    check(vs_int_composite_f2b(two, 2, VS_INT_ONE, &s, &used) == VS_OK && used == 2 && s.a == 48960 &&
              s.c[0] == 48960,
          "int composite of two halves is 3/4 (48960)");
    check(vs_int_composite_f2b(two, 2, 30000, &s, &used) == VS_OK && used == 1 && s.a == 32640,
          "int early termination after one sample");

    /* Premultiplied storage (Wittenbrink section 7): the worst case loses 127 levels. */
    check(vs_premultiply(255, 128) == 128 && vs_premultiply(200, 1) == 1 && vs_premultiply(100, 1) == 0,
          "premultiply rounds half up");
    check(vs_unpremultiply(1, 1) == 255 && vs_unpremultiply(0, 0) == 0 && vs_unpremultiply(128, 128) == 255,
          "unpremultiply");

    /* Errors are statuses, never crashes. */
    const VsVolumeU8 wrong = {pair, 2, 2, 2, 1};
    check(vs_int_sample_u8(&wrong, VS_MODE_OPACITY_WEIGHTED, VS_FILTER_TRILINEAR, mid, &s) == VS_ERR_VOLUME,
          "length mismatch is VS_ERR_VOLUME");
    check(vs_int_sample_u8(&vol, 7, VS_FILTER_TRILINEAR, mid, &s) == VS_ERR_ARG, "unknown mode is VS_ERR_ARG");
    check(vs_int_sample_u8(&vol, VS_MODE_OPACITY_WEIGHTED, VS_FILTER_TRIQUADRATIC, mid, &s) == VS_ERR_ARG,
          "no integer B-spline: VS_ERR_ARG");
    check(vs_int_sample_u8(NULL, VS_MODE_OPACITY_WEIGHTED, VS_FILTER_TRILINEAR, mid, &s) == VS_ERR_NULL,
          "null volume is VS_ERR_NULL");
    VsMarch bad = ow;
    bad.step = 0.0f;
    check(vs_cast_u8(&vol, &bad, origin, dir, &px) == VS_ERR_STEP, "zero step is VS_ERR_STEP");
    const float zero[3] = {0.0f, 0.0f, 0.0f};
    check(vs_cast_u8(&vol, &ow, origin, zero, &px) == VS_ERR_RAY, "zero direction is VS_ERR_RAY");
    bad = ow;
    bad.a_stop = 1.5f;
    check(vs_cast_u8(&vol, &bad, origin, dir, &px) == VS_ERR_THRESHOLD, "threshold 1.5 is VS_ERR_THRESHOLD");
    const uint8_t not_assoc[4] = {200, 0, 0, 100};
    const VsVolumeU8 na = {not_assoc, 1, 1, 1, 1};
    check(vs_int_sample_u8(&na, VS_MODE_PREWEIGHTED, VS_FILTER_NEAREST, mid, &s) == VS_ERR_VOLUME,
          "premultiplied color above alpha is VS_ERR_VOLUME");

    printf("%d passed, %d failed\n", checks - failures, failures);
    return failures != 0;
}
