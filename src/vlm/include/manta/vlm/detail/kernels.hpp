#pragma once
/// @file kernels.hpp
/// Private: the hot loops of the steady and unsteady solvers behind one table of function
/// pointers, compiled three times (src/vlm/kernels_impl.inc): for the baseline x86-64
/// instruction set and, where the compiler can, for AVX2 with FMA and for AVX-512 (F, DQ, VL,
/// BW) in translation units of their own (kernels_avx2.cpp, kernels_avx512.cpp, Eigen renamed
/// there so that no inline function compiled for them can be picked by the linker for the rest
/// of the program). `kernels()` picks once, at first use, the AVX2 set where the processor has
/// it, else the baseline; the environment variable MANTA_VLM_KERNELS=baseline forces the
/// baseline set, =avx512 the AVX-512 set (where the processor has it; slower than AVX2 on the
/// AMD EPYC where it was measured, docs/vlm.md). The sets give the same numbers to rounding (fused
/// multiply-adds and wider vectors change the order of the operations only).
///
/// No Eigen types in this interface (the AVX2 unit's Eigen is another namespace): raw arrays,
/// column-major matrices, `long` sizes.

namespace manta::vlm::detail {

/// One set of horseshoes (the lattice, or one of its mirror images with `factor`) as structure
/// of arrays of `HorseshoeRows::padded` entries: bound ends a, b, r0 = b - a and |r0|^2, and
/// r0 and |r0|^2 rounded to single precision (for `horseshoe_row_f`; may be null otherwise).
struct HorseshoeSet {
    double factor = 1.0;
    const double *ax = nullptr, *ay = nullptr, *az = nullptr;
    const double *bx = nullptr, *by = nullptr, *bz = nullptr;
    const double *r0x = nullptr, *r0y = nullptr, *r0z = nullptr, *l2 = nullptr;
    const float *r0x_f = nullptr, *r0y_f = nullptr, *r0z_f = nullptr, *l2_f = nullptr;
};

/// Every horseshoe of the steady solver: sets, squared cores within / across components, the
/// component of each horseshoe, the count (a multiple of 8) and the Prandtl-Glauert factor; the
/// squared cores also rounded to single precision (for `horseshoe_row_f`; may be null otherwise).
struct HorseshoeRows {
    const HorseshoeSet* sets = nullptr;
    int n_sets = 0;
    const double *core_in = nullptr, *core_x = nullptr;
    const int* component = nullptr;
    long padded = 0;
    double beta = 1.0;
    const float *core_in_f = nullptr, *core_x_f = nullptr;
};

/// The kernels.
struct Kernels {
    const char* name;  ///< "baseline" or "avx2"
    /// Velocities (vx, vy, vz: `padded` each) at the stretched point p, of component `comp`, of
    /// every horseshoe of unit circulation, x component divided by beta (steady.cpp, Stretched).
    void (*horseshoe_row)(const HorseshoeRows& h, const double* p, int comp, double* vx, double* vy,
                          double* vz);
    /// `horseshoe_row` in single precision, 8 horseshoes at a time: the differences p - a and
    /// p - b are formed in double precision and rounded, everything after in single precision
    /// (relative error of a velocity about 1e-7 of the largest term). A point within a relative
    /// angle of 1e-6 of a bound segment's line (sin^2 <= 1e-12, rounding noise in single
    /// precision) gets no velocity from that segment, one within 1e-7 |r| of a trailing leg's
    /// line none from that leg.
    void (*horseshoe_row_f)(const HorseshoeRows& h, const double* p, int comp, float* vx, float* vy,
                            float* vz);
    /// C = At^T B: At k x m, B k x n, C m x n, all column-major.
    void (*gemm_tn)(const double* at, long k, long m, const double* b, long n, double* c);
    /// `gemm_tn` in single precision.
    void (*gemm_tn_f)(const float* at, long k, long m, const float* b, long n, float* c);
    /// C = A B in double precision for a single-precision A: A m x k, B k x n, C m x n, all
    /// column-major (the residuals of iterative refinement, dense_lu.hpp).
    void (*gemm_fd)(const float* a, long m, long k, const double* b, long n, double* c);
    /// LU factorisation with partial pivoting, in place, of the n x n column-major matrix a:
    /// P a = L U, L unit lower; perm[i] = row of P a that row i of a becomes.
    void (*lu_factor)(double* a, long n, int* perm);
    /// Solve (L U) X = P B in place for the n x k column-major B with a factorisation of
    /// lu_factor.
    void (*lu_solve)(const double* lu, long n, const int* perm, double* b, long k);
    /// `lu_factor` and `lu_solve` in single precision.
    void (*lu_factor_f)(float* a, long n, int* perm);
    void (*lu_solve_f)(const float* lu, long n, const int* perm, float* b, long k);
    /// Unsteady grid kernel, step 1: for np grid points (x, y, z), r = p - x, rn = sqrt(|r|^2 +
    /// eps2), ri = 1 / rn.
    void (*grid_points)(const double* x, const double* y, const double* z, long np, const double* p,
                        double eps2, double* rx, double* ry, double* rz, double* rn, double* ri);
    /// Unsteady grid kernel, step 2: accumulate into acc (x, y, z: four lanes each) the velocity
    /// of the m segments from point j to point j + step, strengths S, core terms K (unsteady.cpp,
    /// segment_family).
    void (*segment_family)(const double* rx, const double* ry, const double* rz, const double* rn,
                           const double* ri, long m, long step, const double* S, const double* K,
                           double tiny, double* acc);
};

/// The kernel set of this processor (see the file comment).
[[nodiscard]] const Kernels& kernels();
/// The baseline set, the AVX2 set or nullptr where it was not built or the processor lacks AVX2
/// or FMA, and the AVX-512 set or nullptr where it was not built or the processor lacks one of
/// AVX-512 F, DQ, VL, BW, AVX2, FMA (for tests).
[[nodiscard]] const Kernels& baseline_kernels();
[[nodiscard]] const Kernels* avx2_kernels();
[[nodiscard]] const Kernels* avx512_kernels();

}  // namespace manta::vlm::detail
