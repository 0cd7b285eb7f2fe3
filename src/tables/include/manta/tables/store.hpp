#pragma once
/// @file store.hpp
/// The sample store of a campaign: one SQLite database (WAL journal, synchronous FULL) holding
/// every sample a campaign has scheduled or evaluated, so nothing computed is ever lost.
///
/// A sample is a scenario name ("static", "control:elevator", "dynamic"), the query inputs, a
/// status (pending, done, failed), and once evaluated its outputs, wall time, error text and the
/// fingerprint of the source that computed it. (scenario, inputs) is unique: asking for a sample
/// already stored returns the stored one. Points are recorded as pending before they are
/// evaluated and each result is committed on its own, so a campaign killed at any moment and run
/// again finds every finished sample and knows which were in flight. The store remembers the
/// fingerprint of the source; opening it with another is refused unless accepted. Schema:
/// docs/formats.md#sample-store. All member functions are thread-safe.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "manta/aero/source.hpp"

namespace manta::tables {

enum class SampleStatus { pending, done, failed };
[[nodiscard]] std::string_view to_string(SampleStatus s);

/// One stored sample.
struct Sample {
    std::int64_t id = 0;  ///< order of scheduling (increasing)
    std::string scenario;
    aero::AeroQuery<double> query;
    SampleStatus status = SampleStatus::pending;
    aero::SourceResult result;  ///< valid when done
    std::string error;          ///< failed: the error text
    std::string source;         ///< source name that evaluated it
    std::string fingerprint;    ///< source fingerprint that evaluated it
    double wall_time_s = 0.0;   ///< evaluation wall time
    std::string created_at;     ///< UTC ISO 8601, when scheduled
    std::string finished_at;    ///< UTC ISO 8601, when evaluated ("" if pending)
};

/// How to open a store whose recorded fingerprint differs from the current source's.
struct StoreOpenOptions {
    bool restart = false;                ///< delete the store and start empty
    bool accept_changed_source = false;  ///< keep the samples and adopt the new fingerprint
};

class SampleStore {
public:
    /// Open or create the store at `file` for a source with `source_name` and `fingerprint`.
    /// InputError (one line naming the store and both fingerprints, and the two options) if the
    /// store was filled by a source with another fingerprint and neither option is set. IoError if
    /// the file cannot be opened or is not a MANTA sample store.
    [[nodiscard]] static std::unique_ptr<SampleStore> open(const std::filesystem::path& file,
                                                           const std::string& source_name,
                                                           const std::string& fingerprint,
                                                           const StoreOpenOptions& options = {});
    ~SampleStore();
    SampleStore(const SampleStore&) = delete;
    SampleStore& operator=(const SampleStore&) = delete;

    [[nodiscard]] const std::filesystem::path& file() const { return file_; }
    [[nodiscard]] const std::string& fingerprint() const { return fingerprint_; }
    /// The fingerprint the store held before this open accepted a change ("" if none).
    [[nodiscard]] const std::string& replaced_fingerprint() const { return replaced_; }

    /// Every sample (of `scenario`, or all if empty), in scheduling order.
    [[nodiscard]] std::vector<Sample> samples(std::string_view scenario = {}) const;
    /// Schedule the points (one transaction): each point already stored (same scenario and
    /// inputs) keeps its record; the others are inserted as pending. Returns the sample ids in
    /// the order of `points`.
    std::vector<std::int64_t> schedule(std::string_view scenario,
                                       const std::vector<aero::AeroQuery<double>>& points);
    /// Commit a finished evaluation.
    void record_done(std::int64_t id, const aero::SourceResult& r, double wall_time_s);
    /// Commit a failed evaluation with its error text.
    void record_failed(std::int64_t id, const std::string& error, double wall_time_s);
    /// Return the failed samples (of `scenario`, or all) to pending; returns how many.
    int reset_failed(std::string_view scenario = {});

    /// Free-form metadata (key -> value).
    void set_meta(const std::string& key, const std::string& value);
    [[nodiscard]] std::optional<std::string> meta(const std::string& key) const;

    struct Db;

private:
    SampleStore(std::filesystem::path file, std::string source_name, std::string fingerprint);
    std::filesystem::path file_;
    std::string source_name_;
    std::string fingerprint_;
    std::string replaced_;
    std::unique_ptr<Db> db_;
    mutable std::mutex mutex_;
};

}  // namespace manta::tables
