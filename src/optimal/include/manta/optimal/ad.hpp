#pragma once
/// @file ad.hpp
/// Forward-mode automatic differentiation scalars of the optimal-control module.
///
/// `Fwd<V, N>` carries a value of type V and up to N directional derivatives of type V (the
/// number in use is set at run time); `Fwd<V, kDynamic>` carries any number, on the heap (the
/// transcription's fallback for problems with more than kMaxDirections local variables). With V =
/// double it gives exact first derivatives
/// (`Ad1`); nested, Fwd<Fwd<double>> gives exact second derivatives (`Ad2`, forward over
/// forward). Every evaluation recomputes value and derivatives from scratch, so a branch taken
/// on `core::value_of(x)` (table cell, atmosphere layer) is followed at each call: there is no
/// tape to freeze.
///
/// User code written for `double` works unchanged when it spells the functions unqualified
/// after `using std::sin;` etc. (found by argument-dependent lookup) and stores results in the
/// scalar type T (no `auto` is needed, but none hurts: there are no expression templates).
/// Eigen matrices of these scalars work (NumTraits specialised below).

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <type_traits>
#include <utility>
#include <vector>

namespace manta::optimal {

/// Largest number of directional derivatives of one AD evaluation (local variables of a
/// collocation node, or of the boundary function).
inline constexpr int kMaxDirections = 40;

/// Number of directions of the run-time-sized AD scalars (`Fwd<V, kDynamic>`, `Hyper<kDynamic>`):
/// storage on the heap, sized to the directions in use.
inline constexpr int kDynamic = -1;

template <class V, int N>
class Fwd;

namespace detail {
/// Storage of N derivatives: a fixed array (only the first n in use), or for N = kDynamic a
/// vector sized to n. `resize` keeps nothing (callers overwrite every entry in use).
template <class V, int N>
struct DirectionStore {
    std::array<V, N> a;
    void resize(int /*n*/) noexcept {}
    V& operator[](int i) noexcept { return a[static_cast<std::size_t>(i)]; }
    const V& operator[](int i) const noexcept { return a[static_cast<std::size_t>(i)]; }
};
template <class V>
struct DirectionStore<V, kDynamic> {
    std::vector<V> a;
    void resize(int n) { a.resize(static_cast<std::size_t>(n)); }
    V& operator[](int i) noexcept { return a[static_cast<std::size_t>(i)]; }
    const V& operator[](int i) const noexcept { return a[static_cast<std::size_t>(i)]; }
};

template <class T>
struct is_fwd : std::false_type {};
template <class V, int N>
struct is_fwd<Fwd<V, N>> : std::true_type {};
}  // namespace detail

/// Plain double value of a double or (nested) Fwd scalar.
[[nodiscard]] inline double primal(double x) noexcept {
    return x;
}
/// Plain double value of a (nested) Fwd scalar.
template <class V, int N>
[[nodiscard]] double primal(const Fwd<V, N>& x) noexcept {
    return primal(x.value());
}

/// Forward-mode AD scalar: value v and derivatives d[0..n) along n seeded directions.
/// Constants have n = 0 (all derivatives zero) and mix freely with variables.
template <class V, int N = kMaxDirections>
class Fwd {
public:
    using Value = V;  ///< type of the value and of each derivative

    Fwd() = default;
    /// A constant (implicit, so that `2.0 * x` and `T y = 0.0;` work).
    Fwd(double c) : v_(c) {}  // NOLINT(google-explicit-constructor)
    /// A constant from an integer literal.
    template <class I>
    requires std::is_integral_v<I> Fwd(I c) : v_(static_cast<double>(c)) {}  // NOLINT
    /// A constant from a value of the inner type (nested use).
    explicit Fwd(const V& v) requires(!std::is_same_v<V, double>) : v_(v) {}
    Fwd(const Fwd& o) : v_(o.v_), n_(o.n_) {
        d_.resize(n_);
        for (int i = 0; i < n_; ++i) d_[i] = o.d_[i];
    }
    Fwd& operator=(const Fwd& o) {
        if (this != &o) {
            v_ = o.v_;
            n_ = o.n_;
            d_.resize(n_);
            for (int i = 0; i < n_; ++i) d_[i] = o.d_[i];
        }
        return *this;
    }
    /// Moves (run-time-sized storage only: a fixed array is copied over the directions in use).
    Fwd(Fwd&& o) noexcept requires(N == kDynamic)
        : v_(std::move(o.v_)), n_(o.n_), d_(std::move(o.d_)) {}
    Fwd& operator=(Fwd&& o) noexcept requires(N == kDynamic) {
        v_ = std::move(o.v_);
        n_ = o.n_;
        d_ = std::move(o.d_);
        return *this;
    }
    ~Fwd() = default;

    /// The i-th of n independent variables, with value v (derivative 1 along direction i).
    [[nodiscard]] static Fwd variable(const V& v, int n, int i) {
        Fwd r(v, n);
        for (int k = 0; k < n; ++k) r.d_[k] = V(0.0);
        r.d_[i] = V(1.0);
        return r;
    }

    [[nodiscard]] const V& value() const noexcept { return v_; }
    [[nodiscard]] V& value() noexcept { return v_; }
    /// Number of directions carried (0 for a constant).
    [[nodiscard]] int size() const noexcept { return n_; }
    /// Derivative along direction i (0 when i >= size()).
    [[nodiscard]] V derivative(int i) const { return i < n_ ? d_[i] : V(0.0); }

    // ---- arithmetic -------------------------------------------------------------------------
    friend Fwd operator+(const Fwd& a) { return a; }
    friend Fwd operator-(const Fwd& a) {
        Fwd r(-a.v_, a.n_);
        for (int i = 0; i < a.n_; ++i) r.d_[i] = -a.d_[i];
        return r;
    }
    friend Fwd operator+(const Fwd& a, const Fwd& b) {
        return combine(a, b, a.v_ + b.v_, V(1.0), V(1.0));
    }
    friend Fwd operator-(const Fwd& a, const Fwd& b) {
        return combine(a, b, a.v_ - b.v_, V(1.0), V(-1.0));
    }
    friend Fwd operator*(const Fwd& a, const Fwd& b) {
        return combine(a, b, a.v_ * b.v_, b.v_, a.v_);
    }
    friend Fwd operator/(const Fwd& a, const Fwd& b) {
        const V inv = V(1.0) / b.v_;
        const V q = a.v_ * inv;
        return combine(a, b, q, inv, -q * inv);
    }
    friend Fwd operator+(const Fwd& a, double c) {
        Fwd r(a);
        r.v_ = r.v_ + c;
        return r;
    }
    friend Fwd operator+(double c, const Fwd& a) { return a + c; }
    friend Fwd operator-(const Fwd& a, double c) { return a + (-c); }
    friend Fwd operator-(double c, const Fwd& a) {
        Fwd r = -a;
        r.v_ = r.v_ + c;
        return r;
    }
    friend Fwd operator*(const Fwd& a, double c) { return scale(a, a.v_ * c, c); }
    friend Fwd operator*(double c, const Fwd& a) { return a * c; }
    friend Fwd operator/(const Fwd& a, double c) { return a * (1.0 / c); }
    friend Fwd operator/(double c, const Fwd& a) {
        const V q = c / a.v_;
        return unary(a, q, -q / a.v_);
    }
    Fwd& operator+=(const Fwd& b) { return *this = *this + b; }
    Fwd& operator-=(const Fwd& b) { return *this = *this - b; }
    Fwd& operator*=(const Fwd& b) { return *this = *this * b; }
    Fwd& operator/=(const Fwd& b) { return *this = *this / b; }
    Fwd& operator+=(double c) {
        v_ = v_ + c;
        return *this;
    }
    Fwd& operator-=(double c) {
        v_ = v_ - c;
        return *this;
    }
    Fwd& operator*=(double c) { return *this = *this * c; }
    Fwd& operator/=(double c) { return *this = *this / c; }

    // ---- comparisons (on the plain value) ---------------------------------------------------
    friend bool operator<(const Fwd& a, const Fwd& b) { return primal(a) < primal(b); }
    friend bool operator<=(const Fwd& a, const Fwd& b) { return primal(a) <= primal(b); }
    friend bool operator>(const Fwd& a, const Fwd& b) { return primal(a) > primal(b); }
    friend bool operator>=(const Fwd& a, const Fwd& b) { return primal(a) >= primal(b); }
    friend bool operator==(const Fwd& a, const Fwd& b) { return primal(a) == primal(b); }
    friend bool operator!=(const Fwd& a, const Fwd& b) { return primal(a) != primal(b); }
    friend bool operator<(const Fwd& a, double b) { return primal(a) < b; }
    friend bool operator<=(const Fwd& a, double b) { return primal(a) <= b; }
    friend bool operator>(const Fwd& a, double b) { return primal(a) > b; }
    friend bool operator>=(const Fwd& a, double b) { return primal(a) >= b; }
    friend bool operator==(const Fwd& a, double b) { return primal(a) == b; }
    friend bool operator!=(const Fwd& a, double b) { return primal(a) != b; }
    friend bool operator<(double a, const Fwd& b) { return a < primal(b); }
    friend bool operator<=(double a, const Fwd& b) { return a <= primal(b); }
    friend bool operator>(double a, const Fwd& b) { return a > primal(b); }
    friend bool operator>=(double a, const Fwd& b) { return a >= primal(b); }

    // ---- elementary functions (found by argument-dependent lookup) ---------------------------
    friend Fwd sin(const Fwd& a) {
        using std::cos;
        using std::sin;
        return unary(a, sin(a.v_), cos(a.v_));
    }
    friend Fwd cos(const Fwd& a) {
        using std::cos;
        using std::sin;
        return unary(a, cos(a.v_), -sin(a.v_));
    }
    friend Fwd tan(const Fwd& a) {
        using std::tan;
        const V t = tan(a.v_);
        return unary(a, t, V(1.0) + t * t);
    }
    friend Fwd asin(const Fwd& a) {
        using std::asin;
        using std::sqrt;
        return unary(a, asin(a.v_), V(1.0) / sqrt(V(1.0) - a.v_ * a.v_));
    }
    friend Fwd acos(const Fwd& a) {
        using std::acos;
        using std::sqrt;
        return unary(a, acos(a.v_), V(-1.0) / sqrt(V(1.0) - a.v_ * a.v_));
    }
    friend Fwd atan(const Fwd& a) {
        using std::atan;
        return unary(a, atan(a.v_), V(1.0) / (V(1.0) + a.v_ * a.v_));
    }
    friend Fwd atan2(const Fwd& y, const Fwd& x) {
        using std::atan2;
        const V r2 = x.v_ * x.v_ + y.v_ * y.v_;
        return combine(y, x, atan2(y.v_, x.v_), x.v_ / r2, -y.v_ / r2);
    }
    friend Fwd atan2(const Fwd& y, double x) { return atan2(y, Fwd(x)); }
    friend Fwd atan2(double y, const Fwd& x) { return atan2(Fwd(y), x); }
    friend Fwd sinh(const Fwd& a) {
        using std::cosh;
        using std::sinh;
        return unary(a, sinh(a.v_), cosh(a.v_));
    }
    friend Fwd cosh(const Fwd& a) {
        using std::cosh;
        using std::sinh;
        return unary(a, cosh(a.v_), sinh(a.v_));
    }
    friend Fwd tanh(const Fwd& a) {
        using std::tanh;
        const V t = tanh(a.v_);
        return unary(a, t, V(1.0) - t * t);
    }
    friend Fwd exp(const Fwd& a) {
        using std::exp;
        const V e = exp(a.v_);
        return unary(a, e, e);
    }
    friend Fwd log(const Fwd& a) {
        using std::log;
        return unary(a, log(a.v_), V(1.0) / a.v_);
    }
    friend Fwd log10(const Fwd& a) {
        using std::log10;
        return unary(a, log10(a.v_), V(1.0 / std::log(10.0)) / a.v_);
    }
    friend Fwd sqrt(const Fwd& a) {
        using std::sqrt;
        const V s = sqrt(a.v_);
        return unary(a, s, V(0.5) / s);
    }
    friend Fwd cbrt(const Fwd& a) {
        using std::cbrt;
        const V c = cbrt(a.v_);
        return unary(a, c, V(1.0 / 3.0) / (c * c));
    }
    friend Fwd abs(const Fwd& a) { return primal(a) < 0.0 ? -a : a; }
    friend Fwd fabs(const Fwd& a) { return abs(a); }
    friend Fwd pow(const Fwd& a, double c) {
        using std::pow;
        if (c == 2.0) return a * a;
        if (c == 1.0) return a;
        if (c == 0.0) return Fwd(1.0);
        return unary(a, pow(a.v_, c), c * pow(a.v_, c - 1.0));
    }
    template <class I>
    requires std::is_integral_v<I>
    friend Fwd pow(const Fwd& a, I c) { return pow(a, static_cast<double>(c)); }
    friend Fwd pow(const Fwd& a, const Fwd& b) {
        using std::log;
        using std::pow;
        const V p = pow(a.v_, b.v_);
        const V db = primal(a) > 0.0 ? V(p * log(a.v_)) : V(0.0);
        return combine(a, b, p, b.v_ * pow(a.v_, b.v_ - V(1.0)), db);
    }
    friend Fwd pow(double c, const Fwd& b) {
        using std::log;
        using std::pow;
        const V p = pow(c, b.v_);
        return unary(b, p, p * std::log(c));
    }
    friend Fwd hypot(const Fwd& a, const Fwd& b) { return sqrt(a * a + b * b); }
    friend Fwd floor(const Fwd& a) {
        using std::floor;
        return Fwd(floor(primal(a)));
    }
    friend Fwd ceil(const Fwd& a) {
        using std::ceil;
        return Fwd(ceil(primal(a)));
    }
    friend Fwd fmin(const Fwd& a, const Fwd& b) { return b < a ? b : a; }
    friend Fwd fmax(const Fwd& a, const Fwd& b) { return a < b ? b : a; }
    friend bool isfinite(const Fwd& a) { return std::isfinite(primal(a)); }
    friend bool isnan(const Fwd& a) { return std::isnan(primal(a)); }

private:
    Fwd(const V& v, int n) : v_(v), n_(n) { d_.resize(n); }

    /// Result with value `val` and derivatives da·a.d + db·b.d.
    static Fwd combine(const Fwd& a, const Fwd& b, const V& val, const V& da, const V& db) {
        const int n = a.n_ > b.n_ ? a.n_ : b.n_;
        Fwd r(val, n);
        if (a.n_ == n && b.n_ == n) {
            for (int i = 0; i < n; ++i) r.d_[i] = da * a.d_[i] + db * b.d_[i];
        } else {
            for (int i = 0; i < n; ++i) {
                if (i < a.n_ && i < b.n_) {
                    r.d_[i] = da * a.d_[i] + db * b.d_[i];
                } else if (i < a.n_) {
                    r.d_[i] = da * a.d_[i];
                } else {
                    r.d_[i] = db * b.d_[i];
                }
            }
        }
        return r;
    }
    /// Result with value `val` and derivatives dv·a.d.
    static Fwd unary(const Fwd& a, const V& val, const V& dv) {
        Fwd r(val, a.n_);
        for (int i = 0; i < a.n_; ++i) r.d_[i] = dv * a.d_[i];
        return r;
    }
    static Fwd scale(const Fwd& a, const V& val, double c) {
        Fwd r(val, a.n_);
        for (int i = 0; i < a.n_; ++i) r.d_[i] = a.d_[i] * c;
        return r;
    }

    V v_{};
    int n_ = 0;
    detail::DirectionStore<V, N> d_;  // only [0, n_) is meaningful
};

/// First-order AD scalar (exact gradients and Jacobians).
using Ad1 = Fwd<double, kMaxDirections>;
/// Second-order AD scalar (forward over forward: exact Hessians).
using Ad2 = Fwd<Ad1, kMaxDirections>;
/// First-order AD scalar with any number of directions (heap storage).
using AdDyn1 = Fwd<double, kDynamic>;

}  // namespace manta::optimal

namespace Eigen {
/// Lets Eigen matrices hold the AD scalars (vector algebra in user dynamics).
template <class V, int N>
struct NumTraits<manta::optimal::Fwd<V, N>> : NumTraits<double> {
    using Real = manta::optimal::Fwd<V, N>;
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
/// Products and sums of AD matrices with plain doubles.
template <class V, int N, typename BinOp>
struct ScalarBinaryOpTraits<manta::optimal::Fwd<V, N>, double, BinOp> {
    using ReturnType = manta::optimal::Fwd<V, N>;
};
template <class V, int N, typename BinOp>
struct ScalarBinaryOpTraits<double, manta::optimal::Fwd<V, N>, BinOp> {
    using ReturnType = manta::optimal::Fwd<V, N>;
};
}  // namespace Eigen
