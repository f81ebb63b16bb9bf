// probe.cl — one diffuse bounce written four ways (see probe.cpp). The arithmetic is the
// same in all four: only the data layout and the SIMD spelling differ.

#define PI_F 3.14159265358979f

// The body once, for a scalar type T (float or float8) and its unsigned type U.
#define WP_PROBE_FUNCS(T, U)                                                              \
    __attribute__((overloadable)) U probe_hash(U x) {                                     \
        U h = x * 747796405u + 2891336453u;                                               \
        U w = ((h >> ((h >> 28u) + 4u)) ^ h) * 277803737u;                                \
        return (w >> 22u) ^ w;                                                            \
    }                                                                                     \
    __attribute__((overloadable)) T probe_unit(U x) {                                     \
        return convert_##T(x >> 8u) * (1.0f / 16777216.0f);                               \
    }                                                                                     \
    /* sin and cos of a in [0, 2pi): fold into [-pi/2, pi/2], Taylor to degree 9/10. */    \
    __attribute__((overloadable)) void probe_sincos(T a, T* s, T* c) {                    \
        T t = a - PI_F; /* sin(a) = -sin(t), cos(a) = -cos(t), t in [-pi, pi) */          \
        T hpi = (T)(0.5f * PI_F);                                                         \
        T far = fabs(t) - hpi;                                                            \
        T sg = copysign((T)1.0f, t);                                                      \
        T tf = far > (T)0.0f ? sg * (T)PI_F - t : t; /* sin(tf) = sin(t) */                \
        T cs = far > (T)0.0f ? (T)1.0f : (T)-1.0f;   /* cos(a) = cs * cos(tf) */          \
        T x2 = tf * tf;                                                                   \
        T sp = tf * (1.0f + x2 * (-1.0f / 6 + x2 * (1.0f / 120 + x2 * (-1.0f / 5040 + x2 / 362880)))); \
        T cp = 1.0f + x2 * (-0.5f + x2 * (1.0f / 24 + x2 * (-1.0f / 720 + x2 * (1.0f / 40320 - x2 / 3628800)))); \
        *s = -sp;                                                                         \
        *c = cs * cp;                                                                     \
    }

WP_PROBE_FUNCS(float, uint)
WP_PROBE_FUNCS(float8, uint8)

// Shared arithmetic on scalar components (used by soa_scalar and soa_lanes8).
#define WP_PROBE_BOUNCE(T, U, id, nx, ny, nz, ax, ay, az, OUT)                            \
    {                                                                                     \
        T u1 = probe_unit(probe_hash(id));                                                \
        T u2 = probe_unit(probe_hash(id ^ 0x9e3779b9u));                                  \
        T r = sqrt(u1), s, c;                                                             \
        probe_sincos(u2 * (2.0f * PI_F), &s, &c);                                         \
        T lx = r * c, ly = r * s, lz = sqrt(fmax((T)0.0f, 1.0f - u1));                    \
        T sign = copysign((T)1.0f, nz);                                                   \
        T a = -1.0f / (sign + nz);                                                        \
        T b = nx * ny * a;                                                                \
        T dx = lx * (1.0f + sign * nx * nx * a) + ly * b + lz * nx;                       \
        T dy = lx * (sign * b) + ly * (sign + ny * ny * a) + lz * ny;                     \
        T dz = lx * (-sign * nx) + ly * (-ny) + lz * nz;                                  \
        OUT(0, dx); OUT(1, dy); OUT(2, dz); OUT(3, ax); OUT(4, ay); OUT(5, az);           \
    }

__kernel void soa_scalar(__global const float* in, __global float* out, uint n) {
    uint i = get_global_id(0);
    if (i >= n) return;
#define OUT1(k, v) out[(k) * n + i] = (v)
    WP_PROBE_BOUNCE(float, uint, i, in[i], in[n + i], in[2 * n + i], in[3 * n + i],
                    in[4 * n + i], in[5 * n + i], OUT1)
}

__kernel void soa_lanes8(__global const float* in, __global float* out, uint n) {
    uint g = get_global_id(0);
    if (8 * g >= n) return;
    uint8 id = (uint8)(8 * g) + (uint8)(0, 1, 2, 3, 4, 5, 6, 7);
#define IN8(k) vload8(0, in + (k) * n + 8 * g)
#define OUT8(k, v) vstore8((v), 0, out + (k) * n + 8 * g)
    WP_PROBE_BOUNCE(float8, uint8, id, IN8(0), IN8(1), IN8(2), IN8(3), IN8(4), IN8(5), OUT8)
}

// soa_scalar with what a real shade kernel has: a material looked up through an index
// (a gather) and a data-dependent branch between two lobes (cosine lobe or mirror).
// Here every path is diffuse (kind 0), so the output equals the others', but the
// compiler cannot know it.
__kernel void soa_branchy(__global const float* in, __global float* out, uint n,
                          __global const int* kind_of) {
    uint i = get_global_id(0);
    if (i >= n) return;
    int kind = kind_of[i & 255u];
    if (kind == 0) {
        WP_PROBE_BOUNCE(float, uint, i, in[i], in[n + i], in[2 * n + i], in[3 * n + i],
                        in[4 * n + i], in[5 * n + i], OUT1)
    } else {
        float nx = in[i], ny = in[n + i], nz = in[2 * n + i];
        out[i] = -nx; out[n + i] = -ny; out[2 * n + i] = -nz;  /* mirror at normal incidence */
        out[3 * n + i] = 1.0f; out[4 * n + i] = 1.0f; out[5 * n + i] = 1.0f;
    }
}

// The renderer's style: float3 values, one path per work-item.
__kernel void aos_float3(__global const float* in, __global float* out, uint n) {
    uint i = get_global_id(0);
    if (i >= n) return;
    float3 nrm = (float3)(in[i], in[n + i], in[2 * n + i]);
    float3 alb = (float3)(in[3 * n + i], in[4 * n + i], in[5 * n + i]);
    float u1 = probe_unit(probe_hash(i));
    float u2 = probe_unit(probe_hash(i ^ 0x9e3779b9u));
    float r = sqrt(u1), s, c;
    probe_sincos(u2 * (2.0f * PI_F), &s, &c);
    float3 l = (float3)(r * c, r * s, sqrt(fmax(0.0f, 1.0f - u1)));
    float sign = copysign(1.0f, nrm.z);
    float a = -1.0f / (sign + nrm.z);
    float b = nrm.x * nrm.y * a;
    float3 t = (float3)(1.0f + sign * nrm.x * nrm.x * a, sign * b, -sign * nrm.x);
    float3 bt = (float3)(b, sign + nrm.y * nrm.y * a, -nrm.y);
    float3 d = l.x * t + l.y * bt + l.z * nrm;
    out[i] = d.x; out[n + i] = d.y; out[2 * n + i] = d.z;
    out[3 * n + i] = alb.x; out[4 * n + i] = alb.y; out[5 * n + i] = alb.z;
}
