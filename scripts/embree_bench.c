/* The Embree 3 baseline for scripts/bench: loads an OBJ (v and f lines),
 * builds a medium-quality BVH (five times, keeping the best time), and
 * traces one primary ray per pixel of a WxH image with the camera of
 * tsd/bench/frame.tcl (looking at the centre of the bounding box from
 * direction (0.25, 0.2, 1), at the distance where the bounding sphere
 * fills a 45 degree field of view), with rtcIntersect1
 * (single rays), then one occlusion ray per hit towards the same light.
 * Prints: triangles build_ms primary_mrays shadow_mrays (tab separated).
 *
 *   cc -O2 -fopenmp scripts/embree_bench.c -lembree3 -lm -o embree_bench
 *   ./embree_bench model.obj 1024 1024 [threads]
 */
#include <embree3/rtcore.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

int main(int argc, char **argv) {
    if (argc < 4) { fprintf(stderr, "usage: embree_bench model.obj W H [threads]\n"); return 2; }
    int W = atoi(argv[2]), H = atoi(argv[3]);
    int threads = argc > 4 ? atoi(argv[4]) : 0;
    if (threads > 0) omp_set_num_threads(threads);
    FILE *f = fopen(argv[1], "r");
    if (!f) { perror(argv[1]); return 1; }
    size_t nv = 0, cv = 1 << 16, nt = 0, ct = 1 << 16;
    float *v = malloc(cv * 12); unsigned *t = malloc(ct * 12);
    char line[4096];
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    while (fgets(line, sizeof line, f)) {
        if (line[0] == 'v' && line[1] == ' ') {
            if (nv == cv) v = realloc(v, (cv *= 2) * 12);
            float *p = v + 3 * nv++;
            sscanf(line + 2, "%f %f %f", p, p + 1, p + 2);
            for (int k = 0; k < 3; k++) { if (p[k] < lo[k]) lo[k] = p[k]; if (p[k] > hi[k]) hi[k] = p[k]; }
        } else if (line[0] == 'f' && line[1] == ' ') {
            long idx[64]; int n = 0; char *s = line + 2;
            while (n < 64) {
                while (*s == ' ' || *s == '\t') s++;
                if (*s == '\n' || *s == 0) break;
                idx[n++] = strtol(s, &s, 10);
                while (*s && *s != ' ' && *s != '\t' && *s != '\n') s++;
            }
            for (int k = 1; k + 1 < n; k++) {
                if (nt == ct) t = realloc(t, (ct *= 2) * 12);
                long a[3] = {idx[0], idx[k], idx[k + 1]};
                for (int j = 0; j < 3; j++) t[3 * nt + j] = (unsigned)(a[j] > 0 ? a[j] - 1 : (long)nv + a[j]);
                nt++;
            }
        }
    }
    fclose(f);
    char cfg[64];
    snprintf(cfg, sizeof cfg, "threads=%d", threads);
    RTCDevice dev = rtcNewDevice(threads > 0 ? cfg : NULL);
    /* The best of five builds (ours is timed the same way). */
    RTCScene scene = NULL;
    double build = 1e30, t0;
    for (int pass = 0; pass < 5; pass++) {
        if (scene) rtcReleaseScene(scene);
        t0 = now();
        scene = rtcNewScene(dev);
        rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_MEDIUM);
        RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
        float *vb = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, nv);
        memcpy(vb, v, nv * 12);
        unsigned *ib = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, nt);
        memcpy(ib, t, nt * 12);
        rtcCommitGeometry(g);
        rtcAttachGeometry(scene, g);
        rtcReleaseGeometry(g);
        rtcCommitScene(scene);
        build = fmin(build, now() - t0);
    }

    float c[3], d = 0, dir[3] = {0.25f, 0.2f, 1.0f};
    float dl = sqrtf(0.25f * 0.25f + 0.04f + 1.0f);
    for (int k = 0; k < 3; k++) { c[k] = 0.5f * (lo[k] + hi[k]); d += (hi[k] - lo[k]) * (hi[k] - lo[k]); }
    float r = 0.5f * sqrtf(d);
    float dist = r / sinf(22.5f * (float)M_PI / 180.0f);
    float from[3], fw[3], right[3], up[3], wup[3] = {0, 1, 0};
    for (int k = 0; k < 3; k++) { from[k] = c[k] + dist * dir[k] / dl; fw[k] = c[k] - from[k]; }
    float fl = sqrtf(fw[0] * fw[0] + fw[1] * fw[1] + fw[2] * fw[2]);
    for (int k = 0; k < 3; k++) fw[k] /= fl;
    right[0] = fw[1] * wup[2] - fw[2] * wup[1]; right[1] = fw[2] * wup[0] - fw[0] * wup[2]; right[2] = fw[0] * wup[1] - fw[1] * wup[0];
    float rl = sqrtf(right[0] * right[0] + right[1] * right[1] + right[2] * right[2]);
    for (int k = 0; k < 3; k++) right[k] /= rl;
    up[0] = right[1] * fw[2] - right[2] * fw[1]; up[1] = right[2] * fw[0] - right[0] * fw[2]; up[2] = right[0] * fw[1] - right[1] * fw[0];
    float th = tanf(22.5f * (float)M_PI / 180.0f), tv = th * H / W;
    float light[3] = {c[0] + dist, c[1] + 2 * dist, c[2] + dist};

    float *hitp = malloc((size_t)W * H * 3 * sizeof(float));
    long hits = 0;
    double prim = 1e30;
    /* Best of five passes, like tsd/bench (the proc bench in frame.tcl). */
    for (int pass = 0; pass < 5; pass++) {
    hits = 0;
    t0 = now();
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : hits)
    for (int y = 0; y < H; y++) {
        struct RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        for (int x = 0; x < W; x++) {
            float sx = (2.0f * (x + 0.5f) / W - 1.0f) * th, sy = (1.0f - 2.0f * (y + 0.5f) / H) * tv;
            struct RTCRayHit rh;
            float dx = fw[0] + sx * right[0] + sy * up[0], dy = fw[1] + sx * right[1] + sy * up[1], dz = fw[2] + sx * right[2] + sy * up[2];
            float n = sqrtf(dx * dx + dy * dy + dz * dz);
            rh.ray.org_x = from[0]; rh.ray.org_y = from[1]; rh.ray.org_z = from[2];
            rh.ray.dir_x = dx / n; rh.ray.dir_y = dy / n; rh.ray.dir_z = dz / n;
            rh.ray.tnear = 0; rh.ray.tfar = INFINITY; rh.ray.mask = -1; rh.ray.flags = 0; rh.ray.time = 0;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(scene, &ctx, &rh);
            float *p = hitp + 3 * ((size_t)y * W + x);
            if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
                hits++;
                p[0] = rh.ray.org_x + rh.ray.tfar * rh.ray.dir_x;
                p[1] = rh.ray.org_y + rh.ray.tfar * rh.ray.dir_y;
                p[2] = rh.ray.org_z + rh.ray.tfar * rh.ray.dir_z;
            } else {
                p[0] = NAN;
            }
        }
    }
    prim = fmin(prim, now() - t0);
    }
    long shadows = 0;
    t0 = now();
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : shadows)
    for (int y = 0; y < H; y++) {
        struct RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        for (int x = 0; x < W; x++) {
            float *p = hitp + 3 * ((size_t)y * W + x);
            if (isnan(p[0])) continue;
            float l[3] = {light[0] - p[0], light[1] - p[1], light[2] - p[2]};
            float ll = sqrtf(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
            float m = fmaxf(fmaxf(fabsf(p[0]), fabsf(p[1])), fmaxf(fabsf(p[2]), 1.0f)) * 1e-4f;
            struct RTCRay ray;
            ray.org_x = p[0] + l[0] / ll * m; ray.org_y = p[1] + l[1] / ll * m; ray.org_z = p[2] + l[2] / ll * m;
            ray.dir_x = l[0] / ll; ray.dir_y = l[1] / ll; ray.dir_z = l[2] / ll;
            ray.tnear = 0; ray.tfar = ll - 2 * m; ray.mask = -1; ray.flags = 0; ray.time = 0;
            rtcOccluded1(scene, &ctx, &ray);
            shadows++;
        }
    }
    double shad = now() - t0;
    printf("%zu\t%.2f\t%.2f\t%.2f\n", nt, build * 1e3, (double)W * H / prim / 1e6, shadows / fmax(shad, 1e-9) / 1e6);
    rtcReleaseScene(scene);
    rtcReleaseDevice(dev);
    return 0;
}
