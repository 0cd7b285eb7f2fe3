#include "manta/core/io.hpp"
#include "manta/core/text.hpp"

#include <fmt/format.h>
#include <unistd.h>
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <system_error>

#include "manta/core/error.hpp"

namespace manta::core {

AtomicFileWriter::AtomicFileWriter(const std::filesystem::path& file) : file_(file) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (file.has_parent_path()) fs::create_directories(file.parent_path(), ec);
    if (ec)
        throw IoError(fmt::format("{}: cannot create directory: {}", file.parent_path().string(),
                                  ec.message()));
    tmp_ = file.string() + fmt::format(".tmp{}", static_cast<long>(::getpid()));
    out_ = std::make_unique<std::ofstream>(tmp_, std::ios::binary | std::ios::trunc);
    if (!*out_) throw IoError(fmt::format("{}: cannot open for writing", tmp_.string()));
}

AtomicFileWriter::~AtomicFileWriter() {
    if (committed_) return;
    out_.reset();
    std::error_code ec;
    std::filesystem::remove(tmp_, ec);
}

void AtomicFileWriter::write(std::string_view text) {
    out_->write(text.data(), static_cast<std::streamsize>(text.size()));
    if (!*out_) throw IoError(fmt::format("{}: write failed", tmp_.string()));
}

void AtomicFileWriter::spill(std::string& buffer, std::size_t threshold) {
    if (buffer.size() < threshold) return;
    write(buffer);
    buffer.clear();
}

void AtomicFileWriter::commit() {
    out_->flush();
    if (!*out_) throw IoError(fmt::format("{}: write failed", tmp_.string()));
    out_.reset();
    std::error_code ec;
    std::filesystem::rename(tmp_, file_, ec);
    if (ec) {
        std::filesystem::remove(tmp_);
        throw IoError(fmt::format("{}: cannot replace file: {}", file_.string(), ec.message()));
    }
    committed_ = true;
}

void write_file_atomic(const std::filesystem::path& file, std::string_view content) {
    AtomicFileWriter w(file);
    w.write(content);
    w.commit();
}

std::string read_file(const std::filesystem::path& file) {
    // An ifstream opens a directory on Linux and reads nothing: say what is wrong instead.
    std::error_code ec;
    if (std::filesystem::is_directory(file, ec))
        throw IoError(fmt::format("{}: is a directory; expected a file", file.string()));
    std::ifstream in(file, std::ios::binary);
    if (!in) throw IoError(fmt::format("{}: cannot open file for reading", file.string()));
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::string format_exact(double v) {
    std::array<char, 64> buf{};
    const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
    return std::string(buf.data(), r.ptr);
}

int CsvTable::find(std::string_view name) const {
    const auto it = std::find(columns.begin(), columns.end(), name);
    return it == columns.end() ? -1 : static_cast<int>(it - columns.begin());
}

std::size_t CsvTable::require(std::string_view name) const {
    const int i = find(name);
    if (i < 0) {
        throw InputError(fmt::format("{}: missing column '{}'; columns present: {}", source, name,
                                     fmt::join(columns, ", ")));
    }
    return static_cast<std::size_t>(i);
}

std::vector<double> CsvTable::column(std::size_t index) const {
    std::vector<double> out;
    out.reserve(rows.size());
    for (const auto& r : rows) out.push_back(r.at(index));
    return out;
}

CsvTable parse_csv(std::string_view text, std::string source) {
    CsvTable t;
    t.source = std::move(source);
    int line_no = 0;
    std::size_t pos = 0;
    bool have_header = false;
    while (pos <= text.size()) {
        const std::size_t nl = text.find('\n', pos);
        std::string_view line =
            text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
        pos = nl == std::string_view::npos ? text.size() + 1 : nl + 1;
        ++line_no;
        line = core::trim_blanks(line);
        if (line.empty()) continue;
        if (line.front() == '#') {
            t.comments.emplace_back(core::trim_blanks(line.substr(1)));
            continue;
        }
        const auto fields = core::split_fields(line);
        if (!have_header) {
            for (std::size_t i = 0; i < fields.size(); ++i) {
                if (fields[i].empty())
                    throw InputError(fmt::format("{}:{}: column {} of the header is empty",
                                                 t.source, line_no, i + 1));
                if (std::find(t.columns.begin(), t.columns.end(), fields[i]) != t.columns.end())
                    throw InputError(fmt::format("{}:{}: column '{}' appears twice in the header",
                                                 t.source, line_no, fields[i]));
                t.columns.emplace_back(fields[i]);
            }
            have_header = true;
            continue;
        }
        if (fields.size() != t.columns.size()) {
            throw InputError(fmt::format("{}:{}: row has {} fields; expected {} as in the header",
                                         t.source, line_no, fields.size(), t.columns.size()));
        }
        std::vector<double> row(fields.size());
        for (std::size_t i = 0; i < fields.size(); ++i) {
            const std::string_view f = fields[i];
            // from_chars rejects an explicit leading '+', which other tools write ("+1.5e+00").
            const std::string_view digits =
                f.size() > 1 && f.front() == '+' && f[1] != '-' && f[1] != '+' ? f.substr(1) : f;
            double v = 0.0;
            const auto r = std::from_chars(digits.data(), digits.data() + digits.size(), v);
            if (f.empty() || r.ec != std::errc() || r.ptr != digits.data() + digits.size()) {
                throw InputError(fmt::format("{}:{}: column '{}' value '{}' is not a number",
                                             t.source, line_no, t.columns[i], f));
            }
            if (!std::isfinite(v)) {
                throw InputError(fmt::format(
                    "{}:{}: column '{}' value '{}' is not finite; expected a finite number",
                    t.source, line_no, t.columns[i], f));
            }
            row[i] = v;
        }
        t.rows.push_back(std::move(row));
        t.row_lines.push_back(line_no);
    }
    if (!have_header)
        throw InputError(fmt::format(
            "{}: no header line found; expected comma-separated column names", t.source));
    return t;
}

CsvTable read_csv(const std::filesystem::path& file) {
    return parse_csv(read_file(file), file.string());
}

std::string to_csv(const std::vector<std::string>& columns,
                   const std::vector<std::vector<double>>& rows,
                   const std::vector<std::string>& comments) {
    std::string out;
    for (const auto& c : comments) out += fmt::format("# {}\n", c);
    out += fmt::format("{}\n", fmt::join(columns, ","));
    for (const auto& r : rows) {
        for (std::size_t i = 0; i < r.size(); ++i) {
            if (i) out += ',';
            out += format_exact(r[i]);
        }
        out += '\n';
    }
    return out;
}

}  // namespace manta::core
