/// @file store.cpp
/// The SQLite sample store (schema: docs/formats.md#sample-store).

#include "manta/tables/store.hpp"

#include <fmt/format.h>
#include <sqlite3.h>

#include <chrono>
#include <ctime>
#include <system_error>

#include "manta/core/error.hpp"

namespace manta::tables {

namespace {

constexpr int store_schema_version = 1;

constexpr const char* schema_sql = R"sql(
CREATE TABLE IF NOT EXISTS meta (
    key   TEXT PRIMARY KEY,
    value TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS samples (
    id          INTEGER PRIMARY KEY AUTOINCREMENT,
    scenario    TEXT NOT NULL,
    alpha       REAL NOT NULL, beta REAL NOT NULL, mach REAL NOT NULL,
    p_hat       REAL NOT NULL, q_hat REAL NOT NULL, r_hat REAL NOT NULL,
    elevator    REAL NOT NULL, aileron REAL NOT NULL, rudder REAL NOT NULL,
    status      TEXT NOT NULL CHECK (status IN ('pending', 'done', 'failed')),
    CL REAL, CD REAL, CY REAL, Cl_roll REAL, Cm_pitch REAL, Cn_yaw REAL,
    CX REAL, CY_body REAL, CZ REAL, CD_induced REAL, CD_profile REAL,
    error       TEXT,
    source      TEXT,
    fingerprint TEXT,
    wall_time_s REAL,
    created_at  TEXT NOT NULL,
    finished_at TEXT,
    UNIQUE (scenario, alpha, beta, mach, p_hat, q_hat, r_hat, elevator, aileron, rudder)
);
)sql";

std::string utc_now() {
    const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return buf;
}

/// +0 for -0 (SQLite does not keep the sign of a zero stored as REAL).
double plus_zero(double x) {
    return x == 0.0 ? 0.0 : x;
}

}  // namespace

std::string_view to_string(SampleStatus s) {
    switch (s) {
        case SampleStatus::pending:
            return "pending";
        case SampleStatus::done:
            return "done";
        case SampleStatus::failed:
            return "failed";
    }
    return "?";
}

/// RAII connection and statement helpers.
struct SampleStore::Db {
    sqlite3* db = nullptr;
    std::filesystem::path file;
    ~Db() {
        if (db) sqlite3_close(db);
    }
    [[noreturn]] void fail(std::string_view what) const {
        throw IoError(fmt::format("sample store '{}': {}: {}", file.string(), what,
                                  db ? sqlite3_errmsg(db) : "cannot open"));
    }
    void exec(const char* sql) const {
        char* msg = nullptr;
        if (sqlite3_exec(db, sql, nullptr, nullptr, &msg) != SQLITE_OK) {
            const std::string m = msg ? msg : "?";
            sqlite3_free(msg);
            throw IoError(fmt::format("sample store '{}': {}", file.string(), m));
        }
    }
};

namespace {

/// One prepared statement, finalised on scope exit.
class Statement {
public:
    Statement(const SampleStore::Db& db, const char* sql) : db_(db) {
        if (sqlite3_prepare_v2(db.db, sql, -1, &s_, nullptr) != SQLITE_OK) db.fail("prepare");
    }
    ~Statement() { sqlite3_finalize(s_); }
    Statement(const Statement&) = delete;
    Statement& operator=(const Statement&) = delete;
    void bind(int i, double v) { check(sqlite3_bind_double(s_, i, v)); }
    void bind(int i, std::int64_t v) { check(sqlite3_bind_int64(s_, i, v)); }
    void bind(int i, const std::string& v) {
        check(sqlite3_bind_text(s_, i, v.c_str(), static_cast<int>(v.size()), SQLITE_TRANSIENT));
    }
    /// True while a row is available.
    bool step() {
        const int rc = sqlite3_step(s_);
        if (rc == SQLITE_ROW) return true;
        if (rc == SQLITE_DONE) return false;
        db_.fail("step");
    }
    void run() {
        while (step()) {
        }
        sqlite3_reset(s_);
    }
    [[nodiscard]] double real(int c) const { return sqlite3_column_double(s_, c); }
    [[nodiscard]] std::int64_t integer(int c) const { return sqlite3_column_int64(s_, c); }
    [[nodiscard]] std::string text(int c) const {
        const auto* t = sqlite3_column_text(s_, c);
        return t ? reinterpret_cast<const char*>(t) : "";
    }
    void reset() {
        sqlite3_reset(s_);
        sqlite3_clear_bindings(s_);
    }

private:
    void check(int rc) const {
        if (rc != SQLITE_OK) db_.fail("bind");
    }
    const SampleStore::Db& db_;
    sqlite3_stmt* s_ = nullptr;
};

/// Transaction guard: BEGIN IMMEDIATE ... COMMIT, rolled back if not committed.
class Transaction {
public:
    explicit Transaction(const SampleStore::Db& db) : db_(db) { db.exec("BEGIN IMMEDIATE"); }
    ~Transaction() {
        if (!done_) sqlite3_exec(db_.db, "ROLLBACK", nullptr, nullptr, nullptr);
    }
    Transaction(const Transaction&) = delete;
    Transaction& operator=(const Transaction&) = delete;
    void commit() {
        db_.exec("COMMIT");
        done_ = true;
    }

private:
    const SampleStore::Db& db_;
    bool done_ = false;
};

SampleStatus parse_status(const std::string& s) {
    if (s == "done") return SampleStatus::done;
    if (s == "failed") return SampleStatus::failed;
    return SampleStatus::pending;
}

}  // namespace

SampleStore::SampleStore(std::filesystem::path file, std::string source_name,
                         std::string fingerprint)
    : file_(std::move(file)),
      source_name_(std::move(source_name)),
      fingerprint_(std::move(fingerprint)),
      db_(std::make_unique<Db>()) {}

SampleStore::~SampleStore() = default;

std::unique_ptr<SampleStore> SampleStore::open(const std::filesystem::path& file,
                                               const std::string& source_name,
                                               const std::string& fingerprint,
                                               const StoreOpenOptions& options) {
    std::error_code ec;
    if (options.restart) {
        for (const char* suffix : {"", "-wal", "-shm", "-journal"})
            std::filesystem::remove(file.string() + suffix, ec);
    }
    if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path(), ec);
    std::unique_ptr<SampleStore> s(new SampleStore(file, source_name, fingerprint));
    Db& db = *s->db_;
    db.file = file;
    if (sqlite3_open_v2(file.string().c_str(), &db.db,
                        SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX,
                        nullptr) != SQLITE_OK)
        db.fail("cannot open");
    sqlite3_busy_timeout(db.db, 10000);
    try {
        db.exec("PRAGMA journal_mode=WAL");
        db.exec("PRAGMA synchronous=FULL");
        db.exec(schema_sql);
    } catch (const IoError&) {
        throw IoError(fmt::format("sample store '{}': not a MANTA sample store (SQLite: {})",
                                  file.string(), sqlite3_errmsg(db.db)));
    }
    const auto version = s->meta("schema_version");
    if (!version) {
        s->set_meta("schema_version", std::to_string(store_schema_version));
        s->set_meta("source", source_name);
        s->set_meta("fingerprint", fingerprint);
        s->set_meta("created_at", utc_now());
        return s;
    }
    if (*version != std::to_string(store_schema_version))
        throw IoError(fmt::format(
            "sample store '{}': schema version {} is not supported; expected {} (run with "
            "--restart to start a new store)",
            file.string(), *version, store_schema_version));
    const std::string old = s->meta("fingerprint").value_or("");
    if (old != fingerprint) {
        if (!options.accept_changed_source)
            throw InputError(fmt::format(
                "sample store '{}' holds samples of source fingerprint '{}' but the source now "
                "has fingerprint '{}'; run with --accept-changed-source to reuse them anyway or "
                "--restart to start a new store",
                file.string(), old, fingerprint));
        s->replaced_ = old;
        s->set_meta("fingerprint", fingerprint);
        s->set_meta("source", source_name);
        const std::string history = s->meta("replaced_fingerprints").value_or("");
        s->set_meta("replaced_fingerprints", history.empty() ? old : history + " " + old);
    }
    return s;
}

std::vector<Sample> SampleStore::samples(std::string_view scenario) const {
    const std::lock_guard lock(mutex_);
    const char* all =
        "SELECT id, scenario, alpha, beta, mach, p_hat, q_hat, r_hat, elevator, aileron, rudder, "
        "status, CL, CD, CY, Cl_roll, Cm_pitch, Cn_yaw, CX, CY_body, CZ, CD_induced, CD_profile, "
        "error, source, "
        "fingerprint, wall_time_s, created_at, finished_at FROM samples ";
    const std::string sql =
        std::string(all) + (scenario.empty() ? "ORDER BY id" : "WHERE scenario = ?1 ORDER BY id");
    Statement st(*db_, sql.c_str());
    if (!scenario.empty()) st.bind(1, std::string(scenario));
    std::vector<Sample> out;
    while (st.step()) {
        Sample s;
        s.id = st.integer(0);
        s.scenario = st.text(1);
        auto& q = s.query;
        q.alpha = st.real(2);
        q.beta = st.real(3);
        q.mach = st.real(4);
        q.p_hat = st.real(5);
        q.q_hat = st.real(6);
        q.r_hat = st.real(7);
        q.elevator = st.real(8);
        q.aileron = st.real(9);
        q.rudder = st.real(10);
        s.status = parse_status(st.text(11));
        auto& r = s.result;
        r.wind = {st.real(12), st.real(13), st.real(14)};
        r.body = {st.real(18), st.real(19), st.real(20), st.real(15), st.real(16), st.real(17)};
        r.CD_induced = st.real(21);
        r.CD_profile = st.real(22);
        s.error = st.text(23);
        s.source = st.text(24);
        s.fingerprint = st.text(25);
        s.wall_time_s = st.real(26);
        s.created_at = st.text(27);
        s.finished_at = st.text(28);
        out.push_back(std::move(s));
    }
    return out;
}

std::vector<std::int64_t> SampleStore::schedule(
    std::string_view scenario, const std::vector<aero::AeroQuery<double>>& points) {
    const std::lock_guard lock(mutex_);
    Transaction tx(*db_);
    Statement ins(*db_,
                  "INSERT OR IGNORE INTO samples (scenario, alpha, beta, mach, p_hat, q_hat, "
                  "r_hat, elevator, aileron, rudder, status, created_at) VALUES (?1, ?2, ?3, ?4, "
                  "?5, ?6, ?7, ?8, ?9, ?10, 'pending', ?11)");
    Statement find(*db_,
                   "SELECT id FROM samples WHERE scenario = ?1 AND alpha = ?2 AND beta = ?3 AND "
                   "mach = ?4 AND p_hat = ?5 AND q_hat = ?6 AND r_hat = ?7 AND elevator = ?8 AND "
                   "aileron = ?9 AND rudder = ?10");
    const std::string sc(scenario);
    const std::string now = utc_now();
    std::vector<std::int64_t> ids;
    for (const auto& q : points) {
        const double v[9] = {q.alpha, q.beta,     q.mach,    q.p_hat, q.q_hat,
                             q.r_hat, q.elevator, q.aileron, q.rudder};
        for (Statement* st : {&ins, &find}) {
            st->reset();
            st->bind(1, sc);
            for (int i = 0; i < 9; ++i) st->bind(i + 2, plus_zero(v[i]));
        }
        ins.bind(11, now);
        ins.run();
        if (!find.step()) db_->fail("schedule");
        ids.push_back(find.integer(0));
        find.reset();
    }
    tx.commit();
    return ids;
}

void SampleStore::record_done(std::int64_t id, const aero::SourceResult& r, double wall_time_s) {
    const std::lock_guard lock(mutex_);
    Statement st(*db_,
                 "UPDATE samples SET status = 'done', CL = ?2, CD = ?3, CY = ?4, Cl_roll = ?5, "
                 "Cm_pitch = ?6, Cn_yaw = ?7, CX = ?8, CY_body = ?9, CZ = ?10, CD_induced = ?11, "
                 "CD_profile = ?12, "
                 "error = NULL, source = ?13, fingerprint = ?14, wall_time_s = ?15, finished_at "
                 "= ?16 WHERE id = ?1");
    st.bind(1, id);
    const double v[11] = {r.wind.CL, r.wind.CD, r.wind.CY, r.body.Cl,    r.body.Cm,   r.body.Cn,
                          r.body.CX, r.body.CY, r.body.CZ, r.CD_induced, r.CD_profile};
    for (int i = 0; i < 11; ++i) st.bind(i + 2, v[i]);
    st.bind(13, source_name_);
    st.bind(14, fingerprint_);
    st.bind(15, wall_time_s);
    st.bind(16, utc_now());
    st.run();
}

void SampleStore::record_failed(std::int64_t id, const std::string& error, double wall_time_s) {
    const std::lock_guard lock(mutex_);
    Statement st(*db_,
                 "UPDATE samples SET status = 'failed', error = ?2, source = ?3, fingerprint = ?4, "
                 "wall_time_s = ?5, finished_at = ?6 WHERE id = ?1");
    st.bind(1, id);
    st.bind(2, error);
    st.bind(3, source_name_);
    st.bind(4, fingerprint_);
    st.bind(5, wall_time_s);
    st.bind(6, utc_now());
    st.run();
}

int SampleStore::reset_failed(std::string_view scenario) {
    const std::lock_guard lock(mutex_);
    const std::string sql =
        std::string("UPDATE samples SET status = 'pending', error = NULL WHERE status = 'failed'") +
        (scenario.empty() ? "" : " AND scenario = ?1");
    Statement st(*db_, sql.c_str());
    if (!scenario.empty()) st.bind(1, std::string(scenario));
    st.run();
    return sqlite3_changes(db_->db);
}

void SampleStore::set_meta(const std::string& key, const std::string& value) {
    const std::lock_guard lock(mutex_);
    Statement st(*db_, "INSERT OR REPLACE INTO meta (key, value) VALUES (?1, ?2)");
    st.bind(1, key);
    st.bind(2, value);
    st.run();
}

std::optional<std::string> SampleStore::meta(const std::string& key) const {
    const std::lock_guard lock(mutex_);
    Statement st(*db_, "SELECT value FROM meta WHERE key = ?1");
    st.bind(1, key);
    if (!st.step()) return std::nullopt;
    return st.text(0);
}

}  // namespace manta::tables
