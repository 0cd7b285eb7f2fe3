#include "manta/vlm/output.hpp"

#include <fmt/format.h>

#include <string>

#include "manta/core/io.hpp"

namespace manta::vlm {

void write_panels_vtu(const std::filesystem::path& file, const Model& model, const Lattice& L,
                      const SteadyResult& r) {
    const int n = L.size();
    std::string s;
    s += "<?xml version=\"1.0\"?>\n";
    s += "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n";
    s += "<UnstructuredGrid>\n";
    s += fmt::format("<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", 4 * n, n);
    s += "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (const auto& c : L.corners)
        for (const auto& p : c) s += fmt::format("{} {} {}\n", p.x(), p.y(), p.z());
    s += "</DataArray>\n</Points>\n<Cells>\n";
    s += "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n";
    for (int i = 0; i < n; ++i)
        s += fmt::format("{} {} {} {}\n", 4 * i, 4 * i + 1, 4 * i + 2, 4 * i + 3);
    s += "</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n";
    for (int i = 0; i < n; ++i) s += fmt::format("{}\n", 4 * (i + 1));
    s += "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (int i = 0; i < n; ++i) s += "9\n";  // VTK_QUAD
    s += "</DataArray>\n</Cells>\n<CellData Scalars=\"dcp\">\n";
    s += "<DataArray type=\"Float64\" Name=\"gamma\" format=\"ascii\">\n";
    for (int i = 0; i < n; ++i) s += fmt::format("{}\n", r.gamma.size() == n ? r.gamma[i] : 0.0);
    s += "</DataArray>\n<DataArray type=\"Float64\" Name=\"dcp\" format=\"ascii\">\n";
    // Delta Cp of a lumped vortex: rho V Gamma |l| / (q A) = 2 Gamma |l| / A per unit speed.
    for (int i = 0; i < n; ++i) {
        const auto k = static_cast<std::size_t>(i);
        const double g = r.gamma.size() == n ? r.gamma[i] : 0.0;
        s += fmt::format("{}\n", 2.0 * g * (L.b[k] - L.a[k]).norm() / L.area[k]);
    }
    s += "</DataArray>\n<DataArray type=\"Int32\" Name=\"surface\" format=\"ascii\">\n";
    for (int i = 0; i < n; ++i)
        s += fmt::format(
            "{}\n",
            L.strips[static_cast<std::size_t>(L.strip[static_cast<std::size_t>(i)])].surface);
    s += "</DataArray>\n</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
    (void)model;
    core::write_file_atomic(file, s);
}

void write_span_loading_csv(const std::filesystem::path& file, const Model& model, const Lattice& L,
                            const SteadyResult& r) {
    std::string s = "surface,mirrored,y,z,chord,width,cl,c_cl_over_cref,gamma\n";
    for (std::size_t t = 0; t < L.strips.size(); ++t) {
        const Strip& st = L.strips[t];
        const double cl = t < r.strips.size() ? r.strips[t].cl : 0.0;
        const double g = t < r.strips.size() ? r.strips[t].circulation : 0.0;
        s += fmt::format(
            "{},{},{},{},{},{},{},{},{}\n",
            model.surfaces[static_cast<std::size_t>(st.surface)].name, st.mirrored ? 1 : 0,
            core::format_exact(st.le_mid.y()), core::format_exact(st.le_mid.z()),
            core::format_exact(st.chord), core::format_exact(st.width), core::format_exact(cl),
            core::format_exact(st.chord * cl / model.reference.chord), core::format_exact(g));
    }
    core::write_file_atomic(file, s);
}

}  // namespace manta::vlm
