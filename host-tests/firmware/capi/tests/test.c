/* C test of the volsample C API: compiled as C99 with `-ffreestanding` (only the freestanding
 * headers), linked against the Rust staticlib, checked against known values: Wittenbrink's
 * fig. 4 pair (opacity-weighted stays white, separate bleeds red), exact integer samples,
 * opacity correction's closed form, compositing, the premultiplied-storage rounding, the
 * per-mode entry points against the dispatching ones, the version, and the error statuses
 * (out untouched on error). Exit status 0 only if every check passes.
 *
 * Runs on the host (io_host.c: output through the C library) and on Cortex-M under QEMU
 * (cortex_m.c: start-up code and semihosting output; see ../test.sh). */
#include <stdint.h>
#include <stddef.h>
#include "volsample.h"

/* Writes a NUL-terminated string: io_host.c or cortex_m.c. */
void vs_test_write(const char *s);

static void put_uint(unsigned n) {
    char buf[12];
    char *p = buf + sizeof buf - 1;
    *p = 0;
    do {
        *--p = (char)('0' + n % 10);
        n /= 10;
    } while (n != 0);
    vs_test_write(p);
}

static int failures = 0;
static int checks = 0;

static void check(int ok, const char *what) {
    checks++;
    if (!ok) {
        failures++;
        vs_test_write("FAIL: ");
        vs_test_write(what);
        vs_test_write("\n");
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

    /* The version of the header is the version of the library. */
    check(vs_version() == VOLSAMPLE_VERSION &&
              VOLSAMPLE_VERSION == VOLSAMPLE_VERSION_MAJOR * 10000 + VOLSAMPLE_VERSION_MINOR * 100 +
                                       VOLSAMPLE_VERSION_PATCH,
          "vs_version() == VOLSAMPLE_VERSION");

    /* Out untouched on error. */
    VsSample sentinel = {{-7.0f, -7.0f, -7.0f}, -7.0f};
    check(vs_cast_u8(&vol, &bad, origin, dir, &sentinel) == VS_ERR_THRESHOLD && sentinel.a == -7.0f &&
              sentinel.c[0] == -7.0f,
          "an error leaves *out untouched (float)");
    VsIntSample isent = {{7, 7, 7}, 7};
    check(vs_int_sample_u8(&wrong, VS_MODE_OPACITY_WEIGHTED, VS_FILTER_TRILINEAR, mid, &isent) ==
                  VS_ERR_VOLUME &&
              isent.a == 7 && isent.c[2] == 7,
          "an error leaves *out untouched (integer)");

    /* Each per-mode entry point gives what the dispatching one gives, bit for bit, and refuses
     * a march naming another mode or filter. A 2x2x2 volume with a premultiplied-valid shell. */
    const uint8_t cube[32] = {200, 100, 50,  255, 10, 10, 10, 20,  90, 80, 70, 128, 5,  5,  5,  5,
                              60,  60,  60,  60,  255, 0, 0, 255, 30, 20, 10, 40,  100, 90, 80, 200};
    const VsVolumeU8 cv = {cube, 8, 2, 2, 2};
    typedef int32_t (*cast_fn)(const VsVolumeU8 *, const VsMarch *, const float *, const float *,
                               VsSample *);
    static const cast_fn casts[3][4] = {
        {vs_cast_u8_separate_nearest, vs_cast_u8_separate_trilinear, vs_cast_u8_separate_trilinear_tree,
         vs_cast_u8_separate_triquadratic},
        {vs_cast_u8_opacity_weighted_nearest, vs_cast_u8_opacity_weighted_trilinear,
         vs_cast_u8_opacity_weighted_trilinear_tree, vs_cast_u8_opacity_weighted_triquadratic},
        {vs_cast_u8_preweighted_nearest, vs_cast_u8_preweighted_trilinear,
         vs_cast_u8_preweighted_trilinear_tree, vs_cast_u8_preweighted_triquadratic},
    };
    typedef int32_t (*int_fn)(const VsVolumeU8 *, const uint32_t *, VsIntSample *);
    static const int_fn ints[3][2] = {
        {vs_int_sample_u8_separate_nearest, vs_int_sample_u8_separate_trilinear},
        {vs_int_sample_u8_opacity_weighted_nearest, vs_int_sample_u8_opacity_weighted_trilinear},
        {vs_int_sample_u8_preweighted_nearest, vs_int_sample_u8_preweighted_trilinear},
    };
    const float o2[3] = {-0.7f, 0.3f, 0.6f}, d2[3] = {1.0f, 0.2f, 0.1f};
    const uint32_t p2[3] = {77, 130, 201};
    int same = 1, refused = 1, nonzero = 0;
    for (uint32_t mode = 0; mode < 3; mode++) {
        for (uint32_t filter = 0; filter < 4; filter++) {
            const VsMarch m = {mode, filter, VS_ORDER_FRONT_TO_BACK, 0.5f, 0.25f, 1.0f};
            VsSample a, b;
            same &= vs_cast_u8(&cv, &m, o2, d2, &a) == VS_OK && casts[mode][filter](&cv, &m, o2, d2, &b) == VS_OK &&
                    a.a == b.a && a.c[0] == b.c[0] && a.c[1] == b.c[1] && a.c[2] == b.c[2];
            nonzero += a.a > 0.0f;
            VsMarch other = m;
            other.filter = (filter + 1) % 4;
            refused &= casts[mode][filter](&cv, &other, o2, d2, &b) == VS_ERR_ARG;
            other = m;
            other.mode = (mode + 1) % 3;
            refused &= casts[mode][filter](&cv, &other, o2, d2, &b) == VS_ERR_ARG;
            if (filter < 2) {
                VsIntSample x, y;
                same &= vs_int_sample_u8(&cv, mode, filter, p2, &x) == VS_OK && ints[mode][filter](&cv, p2, &y) == VS_OK &&
                        x.a == y.a && x.c[0] == y.c[0] && x.c[1] == y.c[1] && x.c[2] == y.c[2];
                nonzero += x.a > 0;
            }
        }
    }
    check(same, "every per-mode entry point equals the dispatching one, bit for bit");
    check(nonzero == 18, "the comparison rays and samples are not transparent");
    check(refused, "a per-mode entry point refuses another mode or filter (VS_ERR_ARG)");

    put_uint((unsigned)(checks - failures));
    vs_test_write(" passed, ");
    put_uint((unsigned)failures);
    vs_test_write(" failed\n");
    return failures != 0;
}
