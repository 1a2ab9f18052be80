// HttpCache's SQLite connection: the file opened in WAL mode with the cache's schema, its statements prepared once,
// and a statement's use that resets it however the use ends.
#pragma once
#include "loaders/net/HttpCache.h"

#include <sqlite3.h>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace sg {

// Why the file could not be opened as a cache: SQLite's (primary) result code and message.
struct HttpCacheDbError : std::runtime_error {
    HttpCacheDbError(int code, const std::string& message) : std::runtime_error(message), code(code) {}
    int code;
    // The file is not a database, is damaged, or is another program's: to be made anew.
    bool notACache() const { return code == SQLITE_NOTADB || code == SQLITE_CORRUPT || code == SQLITE_FORMAT; }
};

struct HttpCache::Db {
    sqlite3* db = nullptr;
    // Statements, by use (their SQL in HttpCacheDb.cpp).
    sqlite3_stmt *find = nullptr, *touch = nullptr, *removeUrl = nullptr, *removeId = nullptr, *insert = nullptr,
                 *insertBody = nullptr, *total = nullptr, *count = nullptr, *oldest = nullptr, *update = nullptr,
                 *select = nullptr, *begin = nullptr, *commit = nullptr, *rollback = nullptr;

    // Opens (or creates) `file`; throws HttpCacheDbError.
    explicit Db(const std::string& file);
    ~Db();
    Db(const Db&) = delete;
    Db& operator=(const Db&) = delete;

    std::string error() const { return sqlite3_errmsg(db); }
    int errorCode() const { return sqlite3_errcode(db) & 0xff; }

private:
    std::vector<sqlite3_stmt*> statements_;
    sqlite3_stmt* prepare(const char* sql);
    void check(int rc, const char* what);
};

// One use of a prepared statement: its parameters bound, its steps, and its reset (bindings cleared) when the use
// ends, so that a read does not hold its snapshot of the database open.
class StatementUse {
public:
    explicit StatementUse(sqlite3_stmt* s) : s_(s) {}
    ~StatementUse() {
        sqlite3_reset(s_);
        sqlite3_clear_bindings(s_);
    }
    StatementUse(const StatementUse&) = delete;
    StatementUse& operator=(const StatementUse&) = delete;

    // Strings and blobs are bound without a copy: they must outlive the use.
    StatementUse& text(int i, const std::string& v) {
        sqlite3_bind_text64(s_, i, v.data(), v.size(), SQLITE_STATIC, SQLITE_UTF8);
        return *this;
    }
    StatementUse& integer(int i, int64_t v) {
        sqlite3_bind_int64(s_, i, v);
        return *this;
    }
    StatementUse& blob(int i, const std::vector<unsigned char>& v) {
        // An empty vector's data() may be null, which SQLite would bind as NULL: a zero-length blob instead.
        if (v.empty())
            sqlite3_bind_zeroblob(s_, i, 0);
        else
            sqlite3_bind_blob64(s_, i, v.data(), v.size(), SQLITE_STATIC);
        return *this;
    }
    int step() { return sqlite3_step(s_); }
    int64_t integerAt(int column) const { return sqlite3_column_int64(s_, column); }
    std::string textAt(int column) const;
    std::vector<unsigned char> blobAt(int column) const;

private:
    sqlite3_stmt* s_;
};

}  // namespace sg
