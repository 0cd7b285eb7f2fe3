#pragma once
/// @file hyper.hpp
/// `Hyper<N>`: a second-order forward-mode AD scalar that carries a value, its gradient and its
/// Hessian (symmetric, packed lower triangle) along up to N seeded directions. It computes the
/// same exact Hessians as forward over forward (`Fwd<Fwd<double>>`, ad.hpp) with about half the
/// arithmetic (symmetry) and a fraction of the memory traffic (no nested temporaries): each
/// operation applies the second-order chain rule
///
///     h(f(a, b)) = f_a h_a + f_b h_b + f_aa g_a g_a' + f_ab (g_a g_b' + g_b g_a') + f_bb g_b g_b'.
///
/// Like `Fwd`, it records nothing between evaluations (branches follow the plain value), mixes
/// with `double` constants, and works in Eigen matrices (NumTraits below). Used for the
/// Hessians of the transcription (model.hpp). `Hyper<kDynamic>` (ad.hpp) sizes its storage to
/// the directions in use, on the heap: the fallback beyond kMaxDirections local variables.

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <type_traits>
#include <utility>

#include "manta/optimal/ad.hpp"

namespace manta::optimal {

/// Second-order forward AD scalar (value, gradient, packed symmetric Hessian); see the file
/// comment. Constants have n = 0 directions.
template <int N>
class Hyper {
public:
    static constexpr int kPacked = N * (N + 1) / 2;  ///< entries of the packed Hessian
    using Value = double;                            ///< type of the value

    Hyper() = default;
    /// A constant (implicit, so that `2.0 * x` and `T y = 0.0;` work).
    Hyper(double c) : v_(c) {}  // NOLINT(google-explicit-constructor)
    /// A constant from an integer literal.
    template <class I>
    requires std::is_integral_v<I> Hyper(I c) : v_(static_cast<double>(c)) {}  // NOLINT
    Hyper(const Hyper& o) : v_(o.v_), n_(o.n_) { copy_from(o); }
    Hyper& operator=(const Hyper& o) {
        if (this != &o) {
            v_ = o.v_;
            n_ = o.n_;
            copy_from(o);
        }
        return *this;
    }
    /// Moves (run-time-sized storage only: fixed arrays are copied over the entries in use).
    Hyper(Hyper&& o) noexcept requires(N == kDynamic)
        : v_(o.v_), n_(o.n_), g_(std::move(o.g_)), h_(std::move(o.h_)) {}
    Hyper& operator=(Hyper&& o) noexcept requires(N == kDynamic) {
        v_ = o.v_;
        n_ = o.n_;
        g_ = std::move(o.g_);
        h_ = std::move(o.h_);
        return *this;
    }
    ~Hyper() = default;

    /// The i-th of n independent variables, with value v (gradient e_i, Hessian 0).
    [[nodiscard]] static Hyper variable(double v, int n, int i) {
        Hyper r(v, n);
        for (int k = 0; k < n; ++k) r.g_[k] = 0.0;
        for (int k = 0; k < packed(n); ++k) r.h_[k] = 0.0;
        r.g_[i] = 1.0;
        return r;
    }

    [[nodiscard]] double value() const noexcept { return v_; }
    /// Number of directions carried (0 for a constant).
    [[nodiscard]] int size() const noexcept { return n_; }
    /// First derivative along direction i (0 when i >= size()).
    [[nodiscard]] double gradient(int i) const { return i < n_ ? g_[i] : 0.0; }
    /// Second derivative along directions i and j (0 outside size()).
    [[nodiscard]] double hessian(int i, int j) const {
        if (i >= n_ || j >= n_) return 0.0;
        return i >= j ? h_[i * (i + 1) / 2 + j] : h_[j * (j + 1) / 2 + i];
    }

    // ---- arithmetic -------------------------------------------------------------------------
    friend Hyper operator+(const Hyper& a) { return a; }
    friend Hyper operator-(const Hyper& a) { return linear(a, -a.v_, -1.0); }
    friend Hyper operator+(const Hyper& a, const Hyper& b) {
        return combine(a, b, a.v_ + b.v_, 1.0, 1.0, 0.0, 0.0, 0.0);
    }
    friend Hyper operator-(const Hyper& a, const Hyper& b) {
        return combine(a, b, a.v_ - b.v_, 1.0, -1.0, 0.0, 0.0, 0.0);
    }
    friend Hyper operator*(const Hyper& a, const Hyper& b) {
        return combine(a, b, a.v_ * b.v_, b.v_, a.v_, 0.0, 1.0, 0.0);
    }
    friend Hyper operator/(const Hyper& a, const Hyper& b) {
        const double inv = 1.0 / b.v_;
        const double q = a.v_ * inv;
        return combine(a, b, q, inv, -q * inv, 0.0, -inv * inv, 2.0 * q * inv * inv);
    }
    friend Hyper operator+(const Hyper& a, double c) {
        Hyper r(a);
        r.v_ += c;
        return r;
    }
    friend Hyper operator+(double c, const Hyper& a) { return a + c; }
    friend Hyper operator-(const Hyper& a, double c) { return a + (-c); }
    friend Hyper operator-(double c, const Hyper& a) { return linear(a, c - a.v_, -1.0); }
    friend Hyper operator*(const Hyper& a, double c) { return linear(a, a.v_ * c, c); }
    friend Hyper operator*(double c, const Hyper& a) { return linear(a, a.v_ * c, c); }
    friend Hyper operator/(const Hyper& a, double c) { return a * (1.0 / c); }
    friend Hyper operator/(double c, const Hyper& a) {
        const double inv = 1.0 / a.v_;
        const double q = c * inv;
        return unary(a, q, -q * inv, 2.0 * q * inv * inv);
    }
    Hyper& operator+=(const Hyper& b) { return *this = *this + b; }
    Hyper& operator-=(const Hyper& b) { return *this = *this - b; }
    Hyper& operator*=(const Hyper& b) { return *this = *this * b; }
    Hyper& operator/=(const Hyper& b) { return *this = *this / b; }
    Hyper& operator+=(double c) {
        v_ += c;
        return *this;
    }
    Hyper& operator-=(double c) {
        v_ -= c;
        return *this;
    }
    Hyper& operator*=(double c) { return *this = *this * c; }
    Hyper& operator/=(double c) { return *this = *this / c; }

    // ---- comparisons (on the plain value) ---------------------------------------------------
    friend bool operator<(const Hyper& a, const Hyper& b) { return a.v_ < b.v_; }
    friend bool operator<=(const Hyper& a, const Hyper& b) { return a.v_ <= b.v_; }
    friend bool operator>(const Hyper& a, const Hyper& b) { return a.v_ > b.v_; }
    friend bool operator>=(const Hyper& a, const Hyper& b) { return a.v_ >= b.v_; }
    friend bool operator==(const Hyper& a, const Hyper& b) { return a.v_ == b.v_; }
    friend bool operator!=(const Hyper& a, const Hyper& b) { return a.v_ != b.v_; }
    friend bool operator<(const Hyper& a, double b) { return a.v_ < b; }
    friend bool operator<=(const Hyper& a, double b) { return a.v_ <= b; }
    friend bool operator>(const Hyper& a, double b) { return a.v_ > b; }
    friend bool operator>=(const Hyper& a, double b) { return a.v_ >= b; }
    friend bool operator==(const Hyper& a, double b) { return a.v_ == b; }
    friend bool operator!=(const Hyper& a, double b) { return a.v_ != b; }
    friend bool operator<(double a, const Hyper& b) { return a < b.v_; }
    friend bool operator<=(double a, const Hyper& b) { return a <= b.v_; }
    friend bool operator>(double a, const Hyper& b) { return a > b.v_; }
    friend bool operator>=(double a, const Hyper& b) { return a >= b.v_; }

    // ---- elementary functions: value, first and second derivative ---------------------------
    friend Hyper sin(const Hyper& a) {
        const double s = std::sin(a.v_), c = std::cos(a.v_);
        return unary(a, s, c, -s);
    }
    friend Hyper cos(const Hyper& a) {
        const double s = std::sin(a.v_), c = std::cos(a.v_);
        return unary(a, c, -s, -c);
    }
    friend Hyper tan(const Hyper& a) {
        const double t = std::tan(a.v_);
        const double d = 1.0 + t * t;
        return unary(a, t, d, 2.0 * t * d);
    }
    friend Hyper asin(const Hyper& a) {
        const double w = 1.0 - a.v_ * a.v_;
        const double d = 1.0 / std::sqrt(w);
        return unary(a, std::asin(a.v_), d, a.v_ * d / w);
    }
    friend Hyper acos(const Hyper& a) {
        const double w = 1.0 - a.v_ * a.v_;
        const double d = 1.0 / std::sqrt(w);
        return unary(a, std::acos(a.v_), -d, -a.v_ * d / w);
    }
    friend Hyper atan(const Hyper& a) {
        const double d = 1.0 / (1.0 + a.v_ * a.v_);
        return unary(a, std::atan(a.v_), d, -2.0 * a.v_ * d * d);
    }
    friend Hyper atan2(const Hyper& y, const Hyper& x) {
        const double r2 = x.v_ * x.v_ + y.v_ * y.v_;
        const double r4 = r2 * r2;
        return combine(y, x, std::atan2(y.v_, x.v_), x.v_ / r2, -y.v_ / r2, -2.0 * x.v_ * y.v_ / r4,
                       (y.v_ * y.v_ - x.v_ * x.v_) / r4, 2.0 * x.v_ * y.v_ / r4);
    }
    friend Hyper atan2(const Hyper& y, double x) { return atan2(y, Hyper(x)); }
    friend Hyper atan2(double y, const Hyper& x) { return atan2(Hyper(y), x); }
    friend Hyper sinh(const Hyper& a) {
        const double s = std::sinh(a.v_), c = std::cosh(a.v_);
        return unary(a, s, c, s);
    }
    friend Hyper cosh(const Hyper& a) {
        const double s = std::sinh(a.v_), c = std::cosh(a.v_);
        return unary(a, c, s, c);
    }
    friend Hyper tanh(const Hyper& a) {
        const double t = std::tanh(a.v_);
        const double d = 1.0 - t * t;
        return unary(a, t, d, -2.0 * t * d);
    }
    friend Hyper exp(const Hyper& a) {
        const double e = std::exp(a.v_);
        return unary(a, e, e, e);
    }
    friend Hyper log(const Hyper& a) {
        const double inv = 1.0 / a.v_;
        return unary(a, std::log(a.v_), inv, -inv * inv);
    }
    friend Hyper log10(const Hyper& a) {
        const double inv = 1.0 / (a.v_ * std::log(10.0));
        return unary(a, std::log10(a.v_), inv, -inv / a.v_);
    }
    friend Hyper sqrt(const Hyper& a) {
        const double s = std::sqrt(a.v_);
        const double d = 0.5 / s;
        return unary(a, s, d, -0.5 * d / a.v_);
    }
    friend Hyper cbrt(const Hyper& a) {
        const double c = std::cbrt(a.v_);
        const double d = 1.0 / (3.0 * c * c);
        return unary(a, c, d, -2.0 * d / (3.0 * a.v_));
    }
    friend Hyper abs(const Hyper& a) { return a.v_ < 0.0 ? -a : a; }
    friend Hyper fabs(const Hyper& a) { return abs(a); }
    friend Hyper pow(const Hyper& a, double c) {
        if (c == 2.0) return a * a;
        if (c == 1.0) return a;
        if (c == 0.0) return Hyper(1.0);
        const double p2 = std::pow(a.v_, c - 2.0);
        const double p1 = p2 * a.v_;
        return unary(a, p1 * a.v_, c * p1, c * (c - 1.0) * p2);
    }
    template <class I>
    requires std::is_integral_v<I>
    friend Hyper pow(const Hyper& a, I c) { return pow(a, static_cast<double>(c)); }
    friend Hyper pow(const Hyper& a, const Hyper& b) {
        if (a.v_ <= 0.0) return pow(a, b.v_);  // derivative along b undefined: treat b as fixed
        return exp(b * log(a));
    }
    friend Hyper pow(double c, const Hyper& b) {
        const double l = std::log(c);
        const double p = std::pow(c, b.v_);
        return unary(b, p, p * l, p * l * l);
    }
    friend Hyper hypot(const Hyper& a, const Hyper& b) { return sqrt(a * a + b * b); }
    friend Hyper floor(const Hyper& a) { return Hyper(std::floor(a.v_)); }
    friend Hyper ceil(const Hyper& a) { return Hyper(std::ceil(a.v_)); }
    friend Hyper fmin(const Hyper& a, const Hyper& b) { return b < a ? b : a; }
    friend Hyper fmax(const Hyper& a, const Hyper& b) { return a < b ? b : a; }
    friend bool isfinite(const Hyper& a) { return std::isfinite(a.v_); }
    friend bool isnan(const Hyper& a) { return std::isnan(a.v_); }

private:
    Hyper(double v, int n) : v_(v), n_(n) {
        g_.resize(n);
        h_.resize(packed(n));
    }
    static constexpr int packed(int n) { return n * (n + 1) / 2; }

    void copy_from(const Hyper& o) {
        g_.resize(n_);
        h_.resize(packed(n_));
        for (int i = 0; i < n_; ++i) g_[i] = o.g_[i];
        const int m = packed(n_);
        for (int k = 0; k < m; ++k) h_[k] = o.h_[k];
    }

    /// Result c * a with value `val`.
    static Hyper linear(const Hyper& a, double val, double c) {
        Hyper r(val, a.n_);
        for (int i = 0; i < a.n_; ++i) r.g_[i] = c * a.g_[i];
        const int m = packed(a.n_);
        for (int k = 0; k < m; ++k) r.h_[k] = c * a.h_[k];
        return r;
    }

    /// f(a) with value `val`, f' = d1, f'' = d2.
    static Hyper unary(const Hyper& a, double val, double d1, double d2) {
        const int n = a.n_;
        Hyper r(val, n);
        for (int i = 0; i < n; ++i) r.g_[i] = d1 * a.g_[i];
        int k = 0;
        for (int i = 0; i < n; ++i) {
            const double gi = d2 * a.g_[i];
            for (int j = 0; j <= i; ++j, ++k) r.h_[k] = d1 * a.h_[k] + gi * a.g_[j];
        }
        return r;
    }

    /// f(a, b) with value `val` and partial derivatives fa, fb, faa, fab, fbb.
    static Hyper combine(const Hyper& a, const Hyper& b, double val, double fa, double fb,
                         double faa, double fab, double fbb) {
        if (b.n_ == 0) return unary(a, val, fa, faa);
        if (a.n_ == 0) return unary(b, val, fb, fbb);
        const int n = a.n_ > b.n_ ? a.n_ : b.n_;
        Hyper r(val, n);
        if (a.n_ == n && b.n_ == n) {
            for (int i = 0; i < n; ++i) r.g_[i] = fa * a.g_[i] + fb * b.g_[i];
            int k = 0;
            if (faa == 0.0 && fab == 0.0 && fbb == 0.0) {
                const int m = packed(n);
                for (; k < m; ++k) r.h_[k] = fa * a.h_[k] + fb * b.h_[k];
                return r;
            }
            for (int i = 0; i < n; ++i) {
                const double ai = faa * a.g_[i] + fab * b.g_[i];
                const double bi = fab * a.g_[i] + fbb * b.g_[i];
                for (int j = 0; j <= i; ++j, ++k) {
                    r.h_[k] = fa * a.h_[k] + fb * b.h_[k] + ai * a.g_[j] + bi * b.g_[j];
                }
            }
            return r;
        }
        // different sizes: missing directions are zero
        auto ag = [&](int i) { return i < a.n_ ? a.g_[i] : 0.0; };
        auto bg = [&](int i) { return i < b.n_ ? b.g_[i] : 0.0; };
        for (int i = 0; i < n; ++i) r.g_[i] = fa * ag(i) + fb * bg(i);
        int k = 0;
        for (int i = 0; i < n; ++i) {
            const double ai = faa * ag(i) + fab * bg(i);
            const double bi = fab * ag(i) + fbb * bg(i);
            for (int j = 0; j <= i; ++j, ++k) {
                const double ha = i < a.n_ ? a.h_[k] : 0.0;
                const double hb = i < b.n_ ? b.h_[k] : 0.0;
                r.h_[k] = fa * ha + fb * hb + ai * ag(j) + bi * bg(j);
            }
        }
        return r;
    }

    double v_ = 0.0;
    int n_ = 0;
    detail::DirectionStore<double, N> g_;  // only [0, n_) is meaningful
    detail::DirectionStore<double, N == kDynamic ? kDynamic : kPacked>
        h_;  // only [0, n_(n_+1)/2) is meaningful
};

/// Plain double value of a Hyper scalar.
template <int N>
[[nodiscard]] double primal(const Hyper<N>& x) noexcept {
    return x.value();
}

}  // namespace manta::optimal

namespace Eigen {
/// Lets Eigen matrices hold Hyper scalars.
template <int N>
struct NumTraits<manta::optimal::Hyper<N>> : NumTraits<double> {
    using Real = manta::optimal::Hyper<N>;
    using NonInteger = Real;
    using Nested = Real;
    using Literal = double;
    enum {
        IsComplex = 0,
        IsInteger = 0,
        IsSigned = 1,
        RequireInitialization = 1,
        ReadCost = 1,
        AddCost = 3,
        MulCost = 3
    };
};
template <int N, typename BinOp>
struct ScalarBinaryOpTraits<manta::optimal::Hyper<N>, double, BinOp> {
    using ReturnType = manta::optimal::Hyper<N>;
};
template <int N, typename BinOp>
struct ScalarBinaryOpTraits<double, manta::optimal::Hyper<N>, BinOp> {
    using ReturnType = manta::optimal::Hyper<N>;
};
}  // namespace Eigen
