/// @file output.cpp
/// History, surface and restart files of `manta cfd` (output.hpp).

#include "manta/euler/output.hpp"

#include <fmt/format.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"

namespace manta::euler {

namespace {

constexpr char restart_magic[] = "MANTA-EULER-RESTART 2\n";
constexpr char restart_magic_v1[] = "MANTA-EULER-RESTART 1\n";

void put(std::string& s, const void* p, std::size_t n) {
    s.append(static_cast<const char*>(p), n);
}

}  // namespace

std::string history_header() {
    return "iteration,wall_s,log10_res_rho,log10_res_rhou,log10_res_rhov,log10_res_rhow,"
           "log10_res_rhoE,cfl,linear_iterations,linear_residual,CL,CD,CY,CFx,CFy,CFz,CMx,CMy,"
           "CMz,max_res_rho,max_res_x,max_res_y,max_res_z";
}

std::string history_row(const IterationRecord& r) {
    const ForceCoefficients& f = r.forces;
    return fmt::format(
        "{},{:.4f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6g},{},{:.4e},{:.10g},{:.10g},{:.10g},"
        "{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.4e},{:.6g},{:.6g},{:.6g}",
        r.iteration, r.wall_s, r.log10_residual[0], r.log10_residual[1], r.log10_residual[2],
        r.log10_residual[3], r.log10_residual[4], r.cfl, r.linear_iterations, r.linear_residual,
        f.CL, f.CD, f.CY, f.CFx, f.CFy, f.CFz, f.CMx, f.CMy, f.CMz, r.max_residual,
        r.max_residual_at[0], r.max_residual_at[1], r.max_residual_at[2]);
}

void write_surface_csv(const std::filesystem::path& file, const mesh::Mesh& mesh,
                       const std::vector<BoundaryKind>& roles, std::span<const double> primitive,
                       std::span<const double> cp, std::span<const double> mach,
                       std::span<const mesh::Index> file_node) {
    const auto n = static_cast<std::size_t>(mesh.n_nodes());
    if (primitive.size() != 5 * n || cp.size() != n || mach.size() != n)
        throw InputError(fmt::format("surface output: fields for {} nodes expected", n));
    // The wall nodes, each once, with the first wall marker it lies on.
    std::vector<int> marker_of(n, -1);
    for (mesh::Index f = 0; f < mesh.n_faces(); ++f) {
        const int m = mesh.face_marker(f);
        if (roles[static_cast<std::size_t>(m)] != BoundaryKind::wall) continue;
        for (const mesh::Index v : mesh.face(f))
            if (marker_of[static_cast<std::size_t>(v)] < 0)
                marker_of[static_cast<std::size_t>(v)] = m;
    }
    std::string out = "node,marker,x,y,z,rho,u,v,w,p,Cp,Mach\n";
    for (std::size_t i = 0; i < n; ++i) {
        if (marker_of[i] < 0) continue;
        const Eigen::Vector3d x = mesh.node(static_cast<mesh::Index>(i));
        const double* w = primitive.data() + 5 * i;
        out += fmt::format(
            "{},{},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}\n",
            file_node.empty() ? static_cast<std::int64_t>(i) : file_node[i],
            mesh.markers()[static_cast<std::size_t>(marker_of[i])], x.x(), x.y(), x.z(), w[0], w[1],
            w[2], w[3], w[4], cp[i], mach[i]);
    }
    core::write_file_atomic(file, out);
}

std::string mesh_fingerprint(const mesh::Mesh& mesh, std::span<const std::int64_t> global_node,
                             mesh::Index n_owned, const parallel::Communicator& comm) {
    // Per owned node an FNV-1a hash of its global number and coordinates, cut to 16 bits. The
    // sum of these integers stays below 2^53 (exact in a double, so independent of the order
    // of summation and of the partition) for meshes of up to 10^11 nodes.
    double sum = 0.0;
    for (mesh::Index i = 0; i < n_owned; ++i) {
        std::uint64_t h = 1469598103934665603ULL;
        auto mix = [&](const void* p, std::size_t n) {
            const auto* b = static_cast<const unsigned char*>(p);
            for (std::size_t k = 0; k < n; ++k) {
                h ^= b[k];
                h *= 1099511628211ULL;
            }
        };
        const std::int64_t g = global_node[static_cast<std::size_t>(i)];
        mix(&g, sizeof g);
        const Eigen::Vector3d x = mesh.node(i);
        mix(x.data(), 3 * sizeof(double));
        sum += static_cast<double>(h & 0xffffULL);
    }
    const double total = comm.sum(sum);
    const double n = comm.sum(static_cast<double>(n_owned));
    return fmt::format("nodes={:.0f} checksum={:.0f}", n, total);
}

void write_restart(const std::filesystem::path& file, const RestartData& d) {
    const auto n = static_cast<std::uint64_t>(d.U.size() / 5);
    if (!d.U_backoff.empty() && d.U_backoff.size() != d.U.size())
        throw InputError(fmt::format("{}: restart back-off state of {} values for {} nodes",
                                     file.string(), d.U_backoff.size(), n));
    if (!d.limiter.empty() && d.limiter.size() != d.U.size())
        throw InputError(fmt::format("{}: restart limiter of {} values for {} nodes", file.string(),
                                     d.limiter.size(), n));
    std::string s(restart_magic);
    const auto flen = static_cast<std::uint64_t>(d.fingerprint.size());
    put(s, &flen, sizeof flen);
    s += d.fingerprint;
    const IterationState& st = d.state;
    for (const std::int64_t v :
         {std::int64_t{st.iteration}, std::int64_t{st.limiter_frozen ? 1 : 0},
          std::int64_t{st.stall_since}, std::int64_t{st.cycle_since}, std::int64_t{st.backoffs},
          static_cast<std::int64_t>(st.window.size())})
        put(s, &v, sizeof v);
    for (const double v :
         {st.cfl, st.peak_log10_residual, st.best_log10_residual, st.previous_log10_residual,
          st.cfl_cap, st.cfl_good, st.stall_best, d.mach, d.alpha, d.beta})
        put(s, &v, sizeof v);
    for (const auto& w : st.window) put(s, w.data(), 3 * sizeof(double));
    put(s, &n, sizeof n);
    put(s, d.U.data(), d.U.size() * sizeof(double));
    const std::uint64_t has_backoff = d.U_backoff.empty() ? 0 : 1;
    const std::uint64_t has_limiter = d.limiter.empty() ? 0 : 1;
    put(s, &has_backoff, sizeof has_backoff);
    put(s, d.U_backoff.data(), d.U_backoff.size() * sizeof(float));
    put(s, &has_limiter, sizeof has_limiter);
    put(s, d.limiter.data(), d.limiter.size() * sizeof(double));
    core::write_file_atomic(file, s);
}

RestartData read_restart(const std::filesystem::path& file, std::int64_t n_nodes) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw IoError(fmt::format("{}: cannot open the restart file", file.string()));
    const std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string name = file.string();
    std::size_t pos = 0;
    auto get = [&](void* p, std::size_t n) {
        if (pos + n > s.size())
            throw InputError(
                fmt::format("{}: the restart file is truncated at byte {}", name, pos));
        std::memcpy(p, s.data() + pos, n);
        pos += n;
    };
    const std::size_t ml = std::strlen(restart_magic);
    const bool v1 = s.compare(0, ml, restart_magic_v1) == 0;
    if (!v1 && s.compare(0, ml, restart_magic) != 0)
        throw InputError(
            fmt::format("{}: not a MANTA Euler restart file (expected the header "
                        "'MANTA-EULER-RESTART 2' or '... 1')",
                        name));
    pos = ml;
    RestartData d;
    std::uint64_t flen = 0;
    get(&flen, sizeof flen);
    if (flen > 4096) throw InputError(fmt::format("{}: corrupt restart header", name));
    d.fingerprint.resize(flen);
    get(d.fingerprint.data(), flen);
    IterationState& st = d.state;
    std::uint64_t window = 0;
    if (v1) {
        std::int64_t it = 0, frozen = 0;
        get(&it, sizeof it);
        get(&frozen, sizeof frozen);
        st.iteration = static_cast<int>(it);
        get(&st.cfl, sizeof(double));
        get(&st.peak_log10_residual, sizeof(double));
        // The frozen limiter values are not in this format: recompute and freeze them again.
        st.limiter_frozen = false;
        st.cfl_cap = 0.0;  // solve() starts it at solver.cfl_max
        st.cfl_good = st.cfl;
        st.stall_since = st.cycle_since = st.iteration;
    } else {
        std::int64_t v[6];
        get(v, sizeof v);
        st.iteration = static_cast<int>(v[0]);
        st.limiter_frozen = v[1] != 0;
        st.stall_since = static_cast<int>(v[2]);
        st.cycle_since = static_cast<int>(v[3]);
        st.backoffs = static_cast<int>(v[4]);
        if (v[5] < 0 || v[5] > 100000)
            throw InputError(fmt::format("{}: corrupt restart header (window {})", name, v[5]));
        window = static_cast<std::uint64_t>(v[5]);
        for (double* p : {&st.cfl, &st.peak_log10_residual, &st.best_log10_residual,
                          &st.previous_log10_residual, &st.cfl_cap, &st.cfl_good, &st.stall_best})
            get(p, sizeof(double));
    }
    get(&d.mach, sizeof(double));
    get(&d.alpha, sizeof(double));
    get(&d.beta, sizeof(double));
    st.window.resize(window);
    for (auto& w : st.window) get(w.data(), 3 * sizeof(double));
    std::uint64_t n = 0;
    get(&n, sizeof n);
    if (n_nodes > 0 && n != static_cast<std::uint64_t>(n_nodes))
        throw InputError(
            fmt::format("{}: the restart file holds {} nodes; the mesh has {}", name, n, n_nodes));
    if (n > (s.size() - pos) / (5 * sizeof(double)))
        throw InputError(
            fmt::format("{}: the restart file is truncated ({} nodes announced)", name, n));
    d.U.resize(5 * n);
    get(d.U.data(), d.U.size() * sizeof(double));
    if (!v1) {
        std::uint64_t has = 0;
        get(&has, sizeof has);
        if (has != 0) {
            d.U_backoff.resize(5 * n);
            get(d.U_backoff.data(), d.U_backoff.size() * sizeof(float));
        }
        get(&has, sizeof has);
        if (has != 0) {
            d.limiter.resize(5 * n);
            get(d.limiter.data(), d.limiter.size() * sizeof(double));
        }
        // A frozen limiter without values is a scheme without a limiter (JST, first order);
        // the reader of a limited scheme checks that the values are there.
    }
    return d;
}

}  // namespace manta::euler
