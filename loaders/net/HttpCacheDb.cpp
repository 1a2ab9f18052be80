// HttpCache's SQLite file: opened in WAL mode (readers and one writer at a time, across processes), its schema,
// its statements.
#include "loaders/net/internal/HttpCacheDb.h"

namespace sg {

namespace {

constexpr int kSchemaVersion = 1;

// Entries (what a lookup and the LRU order need) apart from bodies, so that marking an entry used does not rewrite
// its body. `used` orders the entries by last use, across processes (a counter: two uses in one second stay in
// order); `size` counts the body, the kept headers and the URL. Triggers keep the total and drop a removed entry's
// body, whoever removes it.
const char* const kSchema = R"(
CREATE TABLE IF NOT EXISTS entries(
    id INTEGER PRIMARY KEY, url TEXT NOT NULL UNIQUE, status INTEGER NOT NULL, headers TEXT NOT NULL,
    vary TEXT NOT NULL, stored INTEGER NOT NULL, accessed INTEGER NOT NULL, used INTEGER NOT NULL,
    size INTEGER NOT NULL);
CREATE INDEX IF NOT EXISTS entries_used ON entries(used);
CREATE TABLE IF NOT EXISTS bodies(id INTEGER PRIMARY KEY, body BLOB NOT NULL);
CREATE TABLE IF NOT EXISTS total(bytes INTEGER NOT NULL);
INSERT INTO total SELECT 0 WHERE NOT EXISTS (SELECT 1 FROM total);
CREATE TRIGGER IF NOT EXISTS entry_added AFTER INSERT ON entries
    BEGIN UPDATE total SET bytes = bytes + NEW.size; END;
CREATE TRIGGER IF NOT EXISTS entry_removed AFTER DELETE ON entries
    BEGIN UPDATE total SET bytes = bytes - OLD.size; DELETE FROM bodies WHERE id = OLD.id; END;
CREATE TRIGGER IF NOT EXISTS entry_resized AFTER UPDATE OF size ON entries
    BEGIN UPDATE total SET bytes = bytes - OLD.size + NEW.size; END;
PRAGMA user_version = 1;
)";

// The next number of the LRU order.
#define SG_NEXT_USE "(SELECT COALESCE(MAX(used), 0) + 1 FROM entries)"

int64_t scalar(sqlite3* db, const char* sql, int* rc) {
    sqlite3_stmt* s = nullptr;
    int64_t v = 0;
    *rc = sqlite3_prepare_v2(db, sql, -1, &s, nullptr);
    if (*rc == SQLITE_OK) {
        *rc = sqlite3_step(s);
        if (*rc == SQLITE_ROW) v = sqlite3_column_int64(s, 0), *rc = SQLITE_OK;
    }
    sqlite3_finalize(s);
    return v;
}

}  // namespace

HttpCache::Db::Db(const std::string& file) {
    const int flags = SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX;  // HttpCache locks
    const int opened = sqlite3_open_v2(file.c_str(), &db, flags, nullptr);
    if (!db) throw HttpCacheDbError(SQLITE_NOMEM, "out of memory");
    check(opened, "cannot open it");
    // Another process may be writing: wait for it rather than fail (a write is one entry, quickly done).
    sqlite3_busy_timeout(db, 10000);
    sqlite3_extended_result_codes(db, 0);
    check(sqlite3_exec(db, "PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL;", nullptr, nullptr, nullptr),
          "cannot use it");
    int rc = SQLITE_OK;
    const int64_t version = scalar(db, "PRAGMA user_version", &rc);
    check(rc, "cannot read it");
    const int64_t tables = scalar(db, "SELECT COUNT(*) FROM sqlite_master", &rc);
    check(rc, "cannot read it");
    // Another program's database (or a later version of this cache): not to be mixed with.
    if (version != kSchemaVersion && (version != 0 || tables != 0))
        throw HttpCacheDbError(SQLITE_FORMAT,
                               "another program's database (schema version " + std::to_string(version) + ")");
    if (version == 0) {
        const std::string create = std::string("BEGIN IMMEDIATE;") + kSchema + "COMMIT;";
        const int made = sqlite3_exec(db, create.c_str(), nullptr, nullptr, nullptr);
        if (made != SQLITE_OK) sqlite3_exec(db, "ROLLBACK", nullptr, nullptr, nullptr);
        check(made, "cannot make the cache's tables");
    }
    find = prepare(
        "SELECT e.id, e.status, e.headers, e.vary, e.stored, b.body FROM entries e JOIN bodies b ON b.id = e.id "
        "WHERE e.url = ?1");
    touch = prepare("UPDATE entries SET used = " SG_NEXT_USE ", accessed = ?2 WHERE id = ?1");
    removeUrl = prepare("DELETE FROM entries WHERE url = ?1");
    removeId = prepare("DELETE FROM entries WHERE id = ?1");
    insert = prepare(
        "INSERT INTO entries(url, status, headers, vary, stored, accessed, used, size) "
        "VALUES(?1, ?2, ?3, ?4, ?5, ?5, " SG_NEXT_USE ", ?6)");
    insertBody = prepare("INSERT INTO bodies(id, body) VALUES(?1, ?2)");
    total = prepare("SELECT bytes FROM total");
    count = prepare("SELECT COUNT(*) FROM entries");
    oldest = prepare("SELECT id FROM entries WHERE id != ?1 ORDER BY used LIMIT 1");
    select = prepare("SELECT id, headers, size FROM entries WHERE url = ?1");
    update = prepare("UPDATE entries SET headers = ?2, stored = ?3, accessed = ?3, size = ?4, used = " SG_NEXT_USE
                     " WHERE id = ?1");
    begin = prepare("BEGIN IMMEDIATE");  // the write lock at once: no deadlock of two readers turning writers
    commit = prepare("COMMIT");
    rollback = prepare("ROLLBACK");
}

#undef SG_NEXT_USE

HttpCache::Db::~Db() {
    for (sqlite3_stmt* s : statements_) sqlite3_finalize(s);
    sqlite3_close(db);
}

sqlite3_stmt* HttpCache::Db::prepare(const char* sql) {
    sqlite3_stmt* s = nullptr;
    check(sqlite3_prepare_v3(db, sql, -1, SQLITE_PREPARE_PERSISTENT, &s, nullptr), "cannot prepare a statement");
    statements_.push_back(s);
    return s;
}

void HttpCache::Db::check(int rc, const char* what) {
    if (rc == SQLITE_OK) return;
    // Thrown from the constructor: the destructor does not run, so the connection is closed here.
    HttpCacheDbError e(rc & 0xff, std::string(what) + ": " + sqlite3_errmsg(db));
    for (sqlite3_stmt* s : statements_) sqlite3_finalize(s);
    statements_.clear();
    sqlite3_close(db);
    db = nullptr;
    throw e;
}

std::string StatementUse::textAt(int column) const {
    const auto* p = reinterpret_cast<const char*>(sqlite3_column_text(s_, column));
    return p ? std::string(p, size_t(sqlite3_column_bytes(s_, column))) : std::string();
}

std::vector<unsigned char> StatementUse::blobAt(int column) const {
    const auto* p = static_cast<const unsigned char*>(sqlite3_column_blob(s_, column));
    return p ? std::vector<unsigned char>(p, p + sqlite3_column_bytes(s_, column)) : std::vector<unsigned char>();
}

}  // namespace sg
