/// @file distributed.cpp
/// Distribution of a mesh from rank 0 (partition, per-process payloads, local meshes), the MPI
/// halo, and gathers and sums over owned nodes.

#include "manta/parallel/distributed.hpp"

#include <fmt/format.h>
#include <mpi.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>

#include "detail/mpi_check.hpp"
#include "manta/core/error.hpp"
#include "manta/parallel/partition.hpp"

namespace manta::parallel {

using detail::mpi_check;
using detail::mpi_count;
using mesh::Index;

namespace {

constexpr int tag_mesh = 7101;
constexpr int tag_halo_ids = 7102;
constexpr int tag_halo = 7103;

/// Flat byte buffer of length-prefixed arrays: the payload rank 0 sends to each process.
class Packer {
public:
    template <class T>
    void put(std::span<const T> values) {
        static_assert(std::is_trivially_copyable_v<T>);
        const std::uint64_t n = values.size();
        append(&n, sizeof n);
        append(values.data(), values.size_bytes());
    }
    template <class T>
    void put_value(const T& value) {
        put(std::span<const T>(&value, 1));
    }
    void put_string(const std::string& s) { put(std::span<const char>(s.data(), s.size())); }
    [[nodiscard]] std::vector<char>& bytes() noexcept { return bytes_; }

private:
    void append(const void* p, std::size_t n) {
        const auto* c = static_cast<const char*>(p);
        bytes_.insert(bytes_.end(), c, c + n);
    }
    std::vector<char> bytes_;
};

/// Reads what a Packer wrote, in the same order; NumericalError if the payload is short.
class Unpacker {
public:
    explicit Unpacker(std::span<const char> bytes) : bytes_(bytes) {}
    template <class T>
    std::vector<T> get() {
        std::uint64_t n = 0;
        take(&n, sizeof n);
        std::vector<T> v(n);
        take(v.data(), n * sizeof(T));
        return v;
    }
    template <class T>
    T get_value() {
        const auto v = get<T>();
        if (v.size() != 1) fail();
        return v[0];
    }
    std::string get_string() {
        const auto v = get<char>();
        return {v.begin(), v.end()};
    }

private:
    void take(void* p, std::size_t n) {
        if (n > bytes_.size() - pos_) fail();
        if (n > 0) std::memcpy(p, bytes_.data() + pos_, n);
        pos_ += n;
    }
    [[noreturn]] static void fail() {
        throw NumericalError("distribute: the mesh payload from rank 0 is truncated");
    }
    std::span<const char> bytes_;
    std::size_t pos_ = 0;
};

/// Kinds of errors carried from one process to all.
enum class ErrorKind : int { none = 0, input = 1, io = 2, numerical = 3, other = 4 };

ErrorKind kind_of(const std::exception& e) {
    if (dynamic_cast<const InputError*>(&e) || dynamic_cast<const ConfigError*>(&e))
        return ErrorKind::input;
    if (dynamic_cast<const IoError*>(&e)) return ErrorKind::io;
    if (dynamic_cast<const NumericalError*>(&e)) return ErrorKind::numerical;
    return ErrorKind::other;
}

[[noreturn]] void throw_kind(ErrorKind kind, const std::string& message) {
    switch (kind) {
        case ErrorKind::input:
            throw InputError(message);
        case ErrorKind::io:
            throw IoError(message);
        default:
            throw NumericalError(message);
    }
}

/// Rank 0 tells every process whether its part of a step failed, and with what; every process
/// then throws that error (rank 0 its own). Collective.
void share_root_outcome(int rank, ErrorKind kind, const std::string& message) {
    int k = static_cast<int>(kind);
    mpi_check(MPI_Bcast(&k, 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Bcast (status)");
    if (k == 0) return;
    std::string text = message;
    int n = static_cast<int>(text.size());
    mpi_check(MPI_Bcast(&n, 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Bcast (status)");
    text.resize(static_cast<std::size_t>(n));
    mpi_check(MPI_Bcast(text.data(), n, MPI_CHAR, 0, MPI_COMM_WORLD), "MPI_Bcast (status)");
    throw_kind(static_cast<ErrorKind>(k), rank == 0 ? text : text + " (reported by rank 0)");
}

/// Everything rank 0 needs to cut the global mesh into per-process payloads.
struct Plan {
    std::vector<int> part;                          ///< owner of each global node
    std::vector<std::vector<Index>> cells_of_part;  ///< ascending cells each process holds
    std::vector<std::vector<Index>> faces_of_part;  ///< ascending boundary faces
    std::vector<std::vector<Index>> owned_of_part;  ///< ascending owned nodes
};

/// The cell of which each boundary face of a finalized mesh is a face.
std::vector<Index> face_cells(const mesh::Mesh& m) {
    const Index nn = m.n_nodes();
    std::vector<std::int64_t> off(static_cast<std::size_t>(nn) + 1, 0);
    for (Index c = 0; c < m.n_cells(); ++c)
        for (Index n : m.cell(c)) ++off[n + 1];
    for (Index n = 0; n < nn; ++n) off[n + 1] += off[n];
    std::vector<Index> cells(static_cast<std::size_t>(off[nn]));
    {
        std::vector<std::int64_t> fill(off.begin(), off.end() - 1);
        for (Index c = 0; c < m.n_cells(); ++c)
            for (Index n : m.cell(c)) cells[fill[n]++] = c;
    }
    // Sorted node list, triangles padded with the largest index (as Mesh::finalize keys faces).
    const auto key = [](std::span<const Index> nodes) {
        constexpr Index pad = std::numeric_limits<Index>::max();
        std::array<Index, 4> k{pad, pad, pad, pad};
        std::copy(nodes.begin(), nodes.end(), k.begin());
        std::sort(k.begin(), k.end());
        return k;
    };
    std::vector<Index> result(static_cast<std::size_t>(m.n_faces()), -1);
    for (Index f = 0; f < m.n_faces(); ++f) {
        const auto fn = m.face(f);
        const auto fk = key(fn);
        for (auto i = off[fn[0]]; i < off[fn[0] + 1] && result[f] < 0; ++i) {
            const Index c = cells[i];
            const auto cn = m.cell(c);
            for (const auto& lf : mesh::cell_faces(m.cell_type(c))) {
                const int nf = lf[3] < 0 ? 3 : 4;
                if (nf != static_cast<int>(fn.size())) continue;
                std::array<Index, 4> nodes{};
                for (int k = 0; k < nf; ++k) nodes[k] = cn[lf[k]];
                if (key(std::span<const Index>(nodes.data(), nf)) == fk) {
                    result[f] = c;
                    break;
                }
            }
        }
        if (result[f] < 0)
            throw InputError(
                fmt::format("{}: boundary face {} is a face of no cell; expected a "
                            "finalized mesh",
                            m.source(), f));
    }
    return result;
}

Plan make_plan(const mesh::Mesh& m, int n_parts) {
    Plan p;
    p.part = partition_nodes(m, n_parts);
    p.cells_of_part.resize(n_parts);
    p.faces_of_part.resize(n_parts);
    p.owned_of_part.resize(n_parts);
    for (Index n = 0; n < m.n_nodes(); ++n) p.owned_of_part[p.part[n]].push_back(n);
    for (int r = 0; r < n_parts; ++r)
        if (p.owned_of_part[r].empty())
            throw InputError(
                fmt::format("{}: METIS left part {} of {} empty ({} nodes); expected "
                            "fewer processes",
                            m.source(), r, n_parts, m.n_nodes()));
    std::vector<char> has(n_parts, 0);
    const auto parts_of_cell = [&](Index c) {
        std::fill(has.begin(), has.end(), 0);
        for (Index n : m.cell(c)) has[p.part[n]] = 1;
    };
    for (Index c = 0; c < m.n_cells(); ++c) {
        parts_of_cell(c);
        for (int r = 0; r < n_parts; ++r)
            if (has[r]) p.cells_of_part[r].push_back(c);
    }
    const auto fc = face_cells(m);
    for (Index f = 0; f < m.n_faces(); ++f) {
        parts_of_cell(fc[f]);
        for (int r = 0; r < n_parts; ++r)
            if (has[r]) p.faces_of_part[r].push_back(f);
    }
    return p;
}

/// The payload of process `r`: its nodes (owned, then ghosts, each ascending), their owners,
/// coordinates, cells, boundary faces and all marker names. `g2l` is a scratch map of global to
/// local numbers, all -1 on entry and on return.
std::vector<char> make_payload(const mesh::Mesh& m, const Plan& p, int r, int n_parts,
                               std::vector<Index>& g2l) {
    const auto& owned = p.owned_of_part[r];
    std::vector<std::int64_t> global(owned.begin(), owned.end());
    std::vector<Index> ghosts;
    for (Index c : p.cells_of_part[r])
        for (Index n : m.cell(c))
            if (p.part[n] != r) ghosts.push_back(n);
    std::sort(ghosts.begin(), ghosts.end());
    ghosts.erase(std::unique(ghosts.begin(), ghosts.end()), ghosts.end());
    global.insert(global.end(), ghosts.begin(), ghosts.end());
    for (std::size_t i = 0; i < global.size(); ++i) g2l[global[i]] = static_cast<Index>(i);

    std::vector<int> ghost_owner(ghosts.size());
    for (std::size_t g = 0; g < ghosts.size(); ++g) ghost_owner[g] = p.part[ghosts[g]];
    std::vector<double> x(3 * global.size());
    for (std::size_t i = 0; i < global.size(); ++i) {
        const auto xi = m.node(static_cast<Index>(global[i]));
        for (int k = 0; k < 3; ++k) x[3 * i + k] = xi[k];
    }
    std::vector<std::uint8_t> cell_types;
    std::vector<Index> cell_nodes;
    for (Index c : p.cells_of_part[r]) {
        cell_types.push_back(static_cast<std::uint8_t>(m.cell_type(c)));
        for (Index n : m.cell(c)) cell_nodes.push_back(g2l[n]);
    }
    std::vector<std::uint8_t> face_types;
    std::vector<Index> face_nodes;
    std::vector<int> face_markers;
    for (Index f : p.faces_of_part[r]) {
        face_types.push_back(static_cast<std::uint8_t>(m.face_type(f)));
        for (Index n : m.face(f)) face_nodes.push_back(g2l[n]);
        face_markers.push_back(m.face_marker(f));
    }
    for (const auto n : global) g2l[n] = -1;

    Packer out;
    out.put_string(fmt::format("{} (part {} of {})", m.source(), r + 1, n_parts));
    out.put_value<std::int64_t>(m.n_nodes());
    out.put_value<std::int64_t>(static_cast<std::int64_t>(owned.size()));
    out.put<std::int64_t>(global);
    out.put<int>(ghost_owner);
    out.put<double>(x);
    out.put<std::uint8_t>(cell_types);
    out.put<Index>(cell_nodes);
    out.put<std::uint8_t>(face_types);
    out.put<Index>(face_nodes);
    out.put<int>(face_markers);
    out.put_value<std::int64_t>(m.n_markers());
    for (const auto& name : m.markers()) out.put_string(name);
    return std::move(out.bytes());
}

/// Build the local mesh from a payload; returns the ghosts' owners too.
LocalMesh build_local(std::span<const char> bytes, std::vector<int>& ghost_owner) {
    Unpacker in(bytes);
    LocalMesh lm;
    lm.mesh = mesh::Mesh(in.get_string());
    lm.n_global_nodes = in.get_value<std::int64_t>();
    lm.n_owned = static_cast<Index>(in.get_value<std::int64_t>());
    lm.global_node = in.get<std::int64_t>();
    ghost_owner = in.get<int>();
    const auto x = in.get<double>();
    const auto cell_types = in.get<std::uint8_t>();
    const auto cell_nodes = in.get<Index>();
    const auto face_types = in.get<std::uint8_t>();
    const auto face_nodes = in.get<Index>();
    const auto face_markers = in.get<int>();
    const auto n_markers = in.get_value<std::int64_t>();
    std::vector<std::string> markers;
    for (std::int64_t k = 0; k < n_markers; ++k) markers.push_back(in.get_string());

    auto& m = lm.mesh;
    const auto nl = static_cast<Index>(lm.global_node.size());
    m.reserve(nl, static_cast<Index>(cell_types.size()), static_cast<Index>(face_types.size()));
    for (Index i = 0; i < nl; ++i) m.add_node({x[3 * i], x[3 * i + 1], x[3 * i + 2]});
    for (const auto& name : markers) m.add_marker(name);
    std::size_t at = 0;
    for (const auto t : cell_types) {
        const auto type = static_cast<mesh::CellType>(t);
        const auto n = static_cast<std::size_t>(mesh::node_count(type));
        m.add_cell(type, std::span<const Index>(cell_nodes.data() + at, n));
        at += n;
    }
    at = 0;
    for (std::size_t f = 0; f < face_types.size(); ++f) {
        const auto type = static_cast<mesh::FaceType>(face_types[f]);
        const auto n = static_cast<std::size_t>(mesh::node_count(type));
        m.add_face(type, std::span<const Index>(face_nodes.data() + at, n), face_markers[f]);
        at += n;
    }
    m.finalize({.allow_unmarked_exposed_faces = true});
    return lm;
}

}  // namespace

void rethrow_root_error(std::exception_ptr root_error, const Communicator& comm) {
    const int rank = comm.rank();
    if (comm.size() == 1 || !detail::is_mpi(comm)) {
        if (root_error && rank == 0) std::rethrow_exception(root_error);
        return;
    }
    ErrorKind kind = ErrorKind::none;
    std::string message;
    if (rank == 0 && root_error) {
        try {
            std::rethrow_exception(root_error);
        } catch (const std::exception& e) {
            kind = kind_of(e);
            message = e.what();
        } catch (...) {
            kind = ErrorKind::other;
            message = "unknown error on rank 0";
        }
    }
    try {
        share_root_outcome(rank, kind, message);
    } catch (...) {
        if (rank == 0 && root_error) std::rethrow_exception(root_error);
        throw;
    }
}

LocalMesh serial_local_mesh(mesh::Mesh global) {
    if (!global.is_finalized())
        throw InputError(fmt::format(
            "{}: distributing a mesh needs a finalized mesh (Mesh::finalize)", global.source()));
    LocalMesh lm;
    lm.n_owned = global.n_nodes();
    lm.n_global_nodes = global.n_nodes();
    lm.global_node.resize(static_cast<std::size_t>(global.n_nodes()));
    for (Index n = 0; n < global.n_nodes(); ++n) lm.global_node[n] = n;
    lm.mesh = std::move(global);
    lm.halo = std::make_unique<SerialHalo>();
    return lm;
}

LocalMesh distribute(const mesh::Mesh* global, const Communicator& comm) {
    const int size = comm.size();
    const int rank = comm.rank();
    if (size == 1) {
        if (global == nullptr)
            throw InputError("distribute: rank 0 has no mesh; expected the global mesh");
        return serial_local_mesh(*global);
    }
    if (!detail::is_mpi(comm))
        throw InputError(fmt::format(
            "distribute: {} processes need an MpiCommunicator; got another communicator", size));

    // Rank 0 plans; a failure there becomes every process's error.
    Plan plan;
    {
        ErrorKind kind = ErrorKind::none;
        std::string message;
        if (rank == 0) {
            try {
                if (global == nullptr)
                    throw InputError("distribute: rank 0 has no mesh; expected the global mesh");
                if (!global->is_finalized())
                    throw InputError(fmt::format(
                        "{}: distributing a mesh needs a finalized mesh (Mesh::finalize)",
                        global->source()));
                plan = make_plan(*global, size);
            } catch (const std::exception& e) {
                kind = kind_of(e);
                message = e.what();
            }
        }
        share_root_outcome(rank, kind, message);
    }

    std::vector<char> mine;
    if (rank == 0) {
        std::vector<Index> g2l(static_cast<std::size_t>(global->n_nodes()), -1);
        for (int r = 1; r < size; ++r) {
            const auto bytes = make_payload(*global, plan, r, size, g2l);
            mpi_check(MPI_Send(bytes.data(), mpi_count(bytes.size(), "a mesh part"), MPI_BYTE, r,
                               tag_mesh, MPI_COMM_WORLD),
                      "MPI_Send (mesh part)");
        }
        mine = make_payload(*global, plan, 0, size, g2l);
        plan = Plan{};
    } else {
        MPI_Status status;
        mpi_check(MPI_Probe(0, tag_mesh, MPI_COMM_WORLD, &status), "MPI_Probe (mesh part)");
        int n = 0;
        mpi_check(MPI_Get_count(&status, MPI_BYTE, &n), "MPI_Get_count (mesh part)");
        mine.resize(static_cast<std::size_t>(n));
        mpi_check(
            MPI_Recv(mine.data(), n, MPI_BYTE, 0, tag_mesh, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
            "MPI_Recv (mesh part)");
    }

    // Every process builds its mesh; if one fails, all throw.
    LocalMesh lm;
    std::vector<int> ghost_owner;
    std::string failure;
    try {
        lm = build_local(mine, ghost_owner);
    } catch (const std::exception& e) {
        failure = e.what();
    }
    std::vector<char>().swap(mine);
    const double failed = comm.max(failure.empty() ? 0.0 : 1.0);
    if (!failure.empty()) throw NumericalError("distribute: " + failure);
    if (failed > 0.0)
        throw NumericalError(fmt::format(
            "distribute: another process failed to build its part of the mesh (rank {} is fine)",
            rank));
    lm.halo = std::make_unique<MpiHalo>(lm.global_node, lm.n_owned, ghost_owner);
    return lm;
}

MpiHalo::MpiHalo(std::span<const std::int64_t> global_node, Index n_owned,
                 std::span<const int> ghost_owner)
    : n_local_(global_node.size()) {
    int size = 1;
    int rank = 0;
    mpi_check(MPI_Comm_size(MPI_COMM_WORLD, &size), "MPI_Comm_size");
    mpi_check(MPI_Comm_rank(MPI_COMM_WORLD, &rank), "MPI_Comm_rank");
    MANTA_REQUIRE(ghost_owner.size() + static_cast<std::size_t>(n_owned) == global_node.size(),
                  "one owner per ghost node");

    // What this process asks each owner for (ghosts ascending in global number, so each
    // request list is ascending too), and how much each process asks of this one.
    std::vector<std::vector<Index>> recv(size);
    std::vector<std::vector<std::int64_t>> asked(size);
    for (std::size_t g = 0; g < ghost_owner.size(); ++g) {
        const int owner = ghost_owner[g];
        if (owner < 0 || owner >= size || owner == rank)
            throw NumericalError(
                fmt::format("halo: ghost node {} has owner {}; expected another "
                            "rank in 0 to {}",
                            global_node[n_owned + g], owner, size - 1));
        recv[owner].push_back(n_owned + static_cast<Index>(g));
        asked[owner].push_back(global_node[n_owned + g]);
    }
    std::vector<int> n_asked(size), n_asked_of_me(size);
    for (int r = 0; r < size; ++r) n_asked[r] = mpi_count(asked[r].size(), "a halo request");
    mpi_check(
        MPI_Alltoall(n_asked.data(), 1, MPI_INT, n_asked_of_me.data(), 1, MPI_INT, MPI_COMM_WORLD),
        "MPI_Alltoall (halo sizes)");
    std::vector<std::vector<std::int64_t>> wanted(size);
    std::vector<MPI_Request> requests;
    for (int r = 0; r < size; ++r)
        if (n_asked_of_me[r] > 0) {
            wanted[r].resize(static_cast<std::size_t>(n_asked_of_me[r]));
            requests.emplace_back();
            mpi_check(MPI_Irecv(wanted[r].data(), n_asked_of_me[r], MPI_INT64_T, r, tag_halo_ids,
                                MPI_COMM_WORLD, &requests.back()),
                      "MPI_Irecv (halo ids)");
        }
    for (int r = 0; r < size; ++r)
        if (n_asked[r] > 0) {
            requests.emplace_back();
            mpi_check(MPI_Isend(asked[r].data(), n_asked[r], MPI_INT64_T, r, tag_halo_ids,
                                MPI_COMM_WORLD, &requests.back()),
                      "MPI_Isend (halo ids)");
        }
    mpi_check(MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE),
              "MPI_Waitall (halo ids)");

    const auto owned_begin = global_node.begin();
    const auto owned_end = global_node.begin() + n_owned;
    for (int r = 0; r < size; ++r) {
        if (recv[r].empty() && wanted[r].empty()) continue;
        Neighbour nb;
        nb.rank = r;
        nb.recv = std::move(recv[r]);
        nb.send.reserve(wanted[r].size());
        for (const auto g : wanted[r]) {
            const auto it = std::lower_bound(owned_begin, owned_end, g);
            if (it == owned_end || *it != g)
                throw NumericalError(fmt::format(
                    "halo: rank {} asks rank {} for global node {}, which it does not own", r, rank,
                    g));
            nb.send.push_back(static_cast<Index>(it - owned_begin));
        }
        n_send_ += nb.send.size();
        n_recv_ += nb.recv.size();
        neighbours_.push_back(std::move(nb));
    }
}

void MpiHalo::exchange(std::span<double> data, int components) const {
    MANTA_REQUIRE(components > 0 && data.size() == n_local_ * static_cast<std::size_t>(components),
                  "halo exchange: data must hold components values per local node");
    const auto nc = static_cast<std::size_t>(components);
    send_buffer_.resize(n_send_ * nc);
    recv_buffer_.resize(n_recv_ * nc);
    std::vector<MPI_Request> requests;
    requests.reserve(2 * neighbours_.size());
    std::size_t at = 0;
    for (const auto& nb : neighbours_) {
        if (!nb.recv.empty()) {
            requests.emplace_back();
            mpi_check(MPI_Irecv(recv_buffer_.data() + at, mpi_count(nb.recv.size() * nc, "a halo"),
                                MPI_DOUBLE, nb.rank, tag_halo, MPI_COMM_WORLD, &requests.back()),
                      "MPI_Irecv (halo)");
        }
        at += nb.recv.size() * nc;
    }
    at = 0;
    for (const auto& nb : neighbours_) {
        double* out = send_buffer_.data() + at;
        for (const Index n : nb.send) {
            const double* in = data.data() + static_cast<std::size_t>(n) * nc;
            out = std::copy(in, in + nc, out);
        }
        if (!nb.send.empty()) {
            requests.emplace_back();
            mpi_check(MPI_Isend(send_buffer_.data() + at, mpi_count(nb.send.size() * nc, "a halo"),
                                MPI_DOUBLE, nb.rank, tag_halo, MPI_COMM_WORLD, &requests.back()),
                      "MPI_Isend (halo)");
        }
        at += nb.send.size() * nc;
    }
    mpi_check(MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE),
              "MPI_Waitall (halo)");
    at = 0;
    for (const auto& nb : neighbours_)
        for (const Index n : nb.recv) {
            std::copy(recv_buffer_.data() + at, recv_buffer_.data() + at + nc,
                      data.data() + static_cast<std::size_t>(n) * nc);
            at += nc;
        }
}

namespace {

/// Check `local` against the local mesh; returns the number of owned values.
std::size_t owned_values(const LocalMesh& lm, std::span<const double> local, int components) {
    const auto nc = static_cast<std::size_t>(components);
    const auto n_owned = static_cast<std::size_t>(lm.n_owned) * nc;
    const auto n_local = static_cast<std::size_t>(lm.n_local()) * nc;
    if (components < 1 || (local.size() != n_owned && local.size() != n_local))
        throw InputError(fmt::format(
            "{}: {} values with {} components per node; expected {} (owned nodes) or {} "
            "(all local nodes)",
            lm.mesh.source(), local.size(), components, n_owned, n_local));
    return n_owned;
}

}  // namespace

std::vector<double> gather_owned(const LocalMesh& lm, std::span<const double> local, int components,
                                 const Communicator& comm) {
    const std::size_t n_values = owned_values(lm, local, components);
    const auto nc = static_cast<std::size_t>(components);
    const auto scatter = [&](std::span<const std::int64_t> ids, std::span<const double> values,
                             std::vector<double>& out) {
        for (std::size_t i = 0; i < ids.size(); ++i)
            std::copy(values.data() + i * nc, values.data() + (i + 1) * nc,
                      out.data() + static_cast<std::size_t>(ids[i]) * nc);
    };
    if (comm.size() == 1 || !detail::is_mpi(comm)) {
        std::vector<double> out(static_cast<std::size_t>(lm.n_global_nodes) * nc, 0.0);
        scatter(std::span(lm.global_node).first(static_cast<std::size_t>(lm.n_owned)),
                local.first(n_values), out);
        return out;
    }
    const int size = comm.size();
    const int rank = comm.rank();
    int n_owned = lm.n_owned;
    std::vector<int> counts(rank == 0 ? size : 0), displs(rank == 0 ? size : 0);
    mpi_check(MPI_Gather(&n_owned, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD),
              "MPI_Gather (owned counts)");
    std::int64_t total = 0;
    for (int r = 0; r < static_cast<int>(counts.size()); ++r) {
        displs[r] = mpi_count(static_cast<std::size_t>(total), "a gather");
        total += counts[r];
    }
    std::vector<std::int64_t> ids(static_cast<std::size_t>(total));
    mpi_check(MPI_Gatherv(lm.global_node.data(), n_owned, MPI_INT64_T, ids.data(), counts.data(),
                          displs.data(), MPI_INT64_T, 0, MPI_COMM_WORLD),
              "MPI_Gatherv (global ids)");
    for (int r = 0; r < static_cast<int>(counts.size()); ++r) {
        counts[r] = mpi_count(static_cast<std::size_t>(counts[r]) * nc, "a gather");
        displs[r] = mpi_count(static_cast<std::size_t>(displs[r]) * nc, "a gather");
    }
    std::vector<double> values(static_cast<std::size_t>(total) * nc);
    mpi_check(MPI_Gatherv(local.data(), mpi_count(n_values, "a gather"), MPI_DOUBLE, values.data(),
                          counts.data(), displs.data(), MPI_DOUBLE, 0, MPI_COMM_WORLD),
              "MPI_Gatherv (values)");
    std::vector<double> out;
    if (rank == 0) {
        // Checked after the collective calls, so that no process is left waiting.
        if (total != lm.n_global_nodes)
            throw NumericalError(fmt::format(
                "gather_owned: the processes own {} nodes; expected {}", total, lm.n_global_nodes));
        out.assign(static_cast<std::size_t>(total) * nc, 0.0);
        scatter(ids, values, out);
    }
    return out;
}

std::vector<double> sum_owned(const LocalMesh& lm, std::span<const double> local, int components,
                              const Communicator& comm) {
    const std::size_t n_values = owned_values(lm, local, components);
    const auto nc = static_cast<std::size_t>(components);
    std::vector<double> sums(nc, 0.0);
    for (std::size_t i = 0; i < n_values; ++i) sums[i % nc] += local[i];
    comm.sum(sums);
    return sums;
}

}  // namespace manta::parallel
