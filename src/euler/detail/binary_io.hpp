#pragma once
/// @file binary_io.hpp
/// Little-endian binary writer and reader of the unsteady checkpoints (the run folder's
/// restart_unsteady.bin, case.cpp; the Euler source's saved runs, unsteady_source.cpp). Private
/// to the euler module.

#include <fmt/format.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "manta/core/error.hpp"

namespace manta::euler::detail {

struct BinOut {
    std::string buf;
    template <class T>
    void put(const T& v) {
        buf.append(reinterpret_cast<const char*>(&v), sizeof(T));
    }
    void put_string(const std::string& v) {
        put(static_cast<std::uint64_t>(v.size()));
        buf += v;
    }
    void put_doubles(const double* p, std::size_t n) {
        put(static_cast<std::uint64_t>(n));
        buf.append(reinterpret_cast<const char*>(p), n * sizeof(double));
    }
};

/// Reads what BinOut wrote; a read past the end is an InputError naming `file`, `what` the file
/// is and `hint` (what to do).
struct BinIn {
    const std::string& buf;
    std::size_t pos = 0;
    std::string file;
    std::string what = "unsteady restart file";
    std::string hint = "run with --restart to start over";
    void need(std::size_t n) const {
        if (n > buf.size() || pos > buf.size() - n)
            throw InputError(fmt::format("{}: truncated {} (byte {} of {}); {}", file, what,
                                         pos + n, buf.size(), hint));
    }
    template <class T>
    T get() {
        need(sizeof(T));
        T v;
        std::memcpy(&v, buf.data() + pos, sizeof(T));
        pos += sizeof(T);
        return v;
    }
    std::string get_string() {
        const auto n = get<std::uint64_t>();
        need(n);
        std::string v = buf.substr(pos, n);
        pos += n;
        return v;
    }
    std::vector<double> get_doubles() {
        const auto n = get<std::uint64_t>();
        if (n > buf.size() / sizeof(double)) need(buf.size() + 1);  // a corrupt count
        need(n * sizeof(double));
        std::vector<double> v(n);
        if (n) std::memcpy(v.data(), buf.data() + pos, n * sizeof(double));
        pos += n * sizeof(double);
        return v;
    }
};

}  // namespace manta::euler::detail
