/// @file halo_timing.cpp
/// Measures what docs/parallel.md reports for a mesh file: partition quality, distribution time
/// and the time of one halo exchange of the five flow variables per node.
///
///     mpirun -np 2 build/tests/parallel/parallel_halo_timing MESH [EXCHANGES [PARTS...]]
///
/// PARTS: further part counts whose METIS partition quality rank 0 reports (not distributed).
/// Rank 0 reads the mesh; every figure is printed by rank 0 (set-up times: the slowest process;
/// exchange times: the mean over the processes of each exchange).

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <exception>
#include <optional>
#include <string>

#include "manta/mesh/dual.hpp"
#include "manta/mesh/readers.hpp"
#include "manta/parallel/distributed.hpp"
#include "manta/parallel/mpi.hpp"
#include "manta/parallel/partition.hpp"

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Processor time of this process since `c0` (s): unlike the wall time, not inflated when the
/// machine is shared.
double cpu_since(std::clock_t c0) {
    return static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
}

int run(int argc, char** argv, const manta::parallel::Communicator& comm) {
    using namespace manta;
    if (argc < 2) {
        if (comm.rank() == 0)
            std::fprintf(stderr, "usage: parallel_halo_timing MESH [EXCHANGES [PARTS...]]\n");
        return 2;
    }
    const int n_exchanges = argc > 2 ? std::stoi(argv[2]) : 2000;
    const bool root = comm.rank() == 0;
    const auto say = [root](const std::string& s) {
        if (root) std::printf("%s\n", s.c_str());
    };

    std::optional<mesh::Mesh> global;
    auto t0 = std::chrono::steady_clock::now();
    if (root) global = mesh::read_mesh(argv[1]);
    const double t_read = seconds_since(t0);
    if (root) {
        say(fmt::format("mesh {}: {} nodes, {} cells, {} boundary faces; read in {:.2f} s", argv[1],
                        global->n_nodes(), global->n_cells(), global->n_faces(), t_read));
        std::vector<int> counts{comm.size()};
        for (int a = 3; a < argc; ++a) counts.push_back(std::stoi(argv[a]));
        for (const int n_parts : counts) {
            t0 = std::chrono::steady_clock::now();
            const auto c0 = std::clock();
            const auto part = parallel::partition_nodes(*global, n_parts);
            const double t_part = seconds_since(t0);
            const double cpu_part = cpu_since(c0);
            const auto q = parallel::partition_quality(*global, part, n_parts);
            std::int64_t ghosts = 0;
            for (const auto g : q.ghosts) ghosts += g;
            say(fmt::format(
                "partition into {}: METIS {:.3f} s ({:.3f} s processor), edge cut {} "
                "of {} edges ({:.2f} %), imbalance {:.4f}, ghosts {} ({:.2f} % of "
                "nodes)",
                n_parts, t_part, cpu_part, q.edge_cut, q.n_edges, 100.0 * q.cut_fraction(),
                q.imbalance, ghosts, 100.0 * static_cast<double>(ghosts) / global->n_nodes()));
            if (n_parts == comm.size())
                for (int p = 0; p < n_parts; ++p)
                    say(fmt::format("  part {}: {} owned, {} ghosts ({:.2f} % of owned)", p,
                                    q.sizes[p], q.ghosts[p], 100.0 * q.ghosts[p] / q.sizes[p]));
        }
    }
    comm.barrier();
    t0 = std::chrono::steady_clock::now();
    auto c0 = std::clock();
    const auto lm = parallel::distribute(global ? &*global : nullptr, comm);
    const double t_dist = comm.max(seconds_since(t0));
    const double cpu_dist = comm.max(cpu_since(c0));
    global.reset();
    t0 = std::chrono::steady_clock::now();
    c0 = std::clock();
    const auto dual = mesh::compute_dual_metrics(lm.mesh);
    const double t_dual = comm.max(seconds_since(t0));
    const double cpu_dual = comm.max(cpu_since(c0));
    say(
        fmt::format("distribute (partition, send, build, finalize, halo lists) {:.3f} s ({:.3f} "
                    "s processor); local dual metrics {:.3f} s ({:.3f} s processor)",
                    t_dist, cpu_dist, t_dual, cpu_dual));

    constexpr int nc = 5;
    std::vector<double> data(static_cast<std::size_t>(lm.n_local()) * nc, 1.0);
    for (int i = 0; i < 10; ++i) lm.halo->exchange(data, nc);  // warm-up
    // Each exchange timed alone (the slowest process's time, since every process waits for its
    // neighbours): the mean includes the waits for a descheduled process on a loaded machine,
    // the median and the minimum show the exchange itself.
    std::vector<double> times(static_cast<std::size_t>(n_exchanges));
    for (auto& t : times) {
        comm.barrier();
        t0 = std::chrono::steady_clock::now();
        lm.halo->exchange(data, nc);
        t = seconds_since(t0);
    }
    comm.sum(times);  // summed over the processes, divided by their number below
    std::sort(times.begin(), times.end());
    double mean = 0.0;
    for (double t : times) mean += t;
    mean /= n_exchanges * comm.size();
    const double median = times[times.size() / 2] / comm.size();
    const double fastest = times.front() / comm.size();
    const double ghost_values = comm.sum(static_cast<double>(lm.n_ghosts()) * nc);
    say(fmt::format(
        "halo exchange of {} values per node ({} exchanges, mean over processes): "
        "mean {:.1f} us, median {:.1f} us, min {:.1f} us; {:.0f} values received in all",
        nc, n_exchanges, 1e6 * mean, 1e6 * median, 1e6 * fastest, ghost_values));
    // A scale for the exchange time: one sweep over the local edges reading both end states.
    double acc = 0.0;
    comm.barrier();
    t0 = std::chrono::steady_clock::now();
    for (int r = 0; r < 20; ++r)
        for (const auto& [i, j] : dual.edges) acc += data[i * nc] * data[j * nc + 4];
    const double t_sweep = comm.max(seconds_since(t0)) / 20;
    say(
        fmt::format("for scale: one trivial sweep over the local edges {:.1f} us ({} edges on "
                    "rank 0, checksum {:.0f})",
                    1e6 * t_sweep, dual.n_edges(), comm.sum(acc)));
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    const manta::parallel::MpiEnvironment env;
    try {
        return run(argc, argv, env.communicator());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
}
