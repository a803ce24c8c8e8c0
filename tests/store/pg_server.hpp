#pragma once
// A throwaway PostgreSQL server for the tests of the central database (Debian's postgresql
// package): initdb and pg_ctl in a folder of its own, listening only on a Unix socket in that
// folder (no TCP port, nothing reachable from outside), password authentication (SCRAM) for
// every role so that credentials matter, fsync off (a test server needs no durability). Run as
// root (CI), the server runs as the unprivileged user 'postgres' the package creates.
//
// One server per test executable where possible: CTest starts one before the central tests
// (fixture `central_pg`, tests/store/CMakeLists.txt) and stops it after; its folder is in
// GYROCAL_TEST_PG_DIR. A test run without it (by hand) starts one for the process, stopped at exit.
// Each test works in a database of its own (NewDatabase).
#include <memory>
#include <string>

namespace gyrocal::testing {

class PgServer {
public:
    // A new server in `dir` (created, or emptied). Throws std::runtime_error with the server's
    // log when it does not start. `durable`: fsync on, as a real server (benchmarks).
    static std::unique_ptr<PgServer> Start(const std::string& dir, bool durable = false);
    // The same, also listening on 127.0.0.1:<a free port> with TLS on (a self-signed certificate
    // made with openssl in `dir`), for the tests of encryption.
    static std::unique_ptr<PgServer> StartWithTls(const std::string& dir);
    int tcp_port() const { return tcp_port_; }  // 0: Unix socket only
    // The server another process started in `dir`, if it is running; nullptr otherwise.
    static std::unique_ptr<PgServer> Attach(const std::string& dir);
    ~PgServer();  // stops the server when this object started it (unless Detach())

    void Stop();     // immediate shutdown (connections are cut)
    void Restart();  // stop (immediate) and start again, same data
    void Detach() { owned_ = false; }
    bool Running() const;

    const std::string& dir() const { return dir_; }
    // postgresql://USER:PASSWORD@/DB?host=DIR&port=PORT (the Unix socket, also with TLS on)
    std::string Url(const std::string& db, const std::string& user = kAdmin,
                    const std::string& password = kAdminPassword) const;
    // A fresh database (a unique name from `prefix`), owned by the admin role; returns its name.
    std::string NewDatabase(const std::string& prefix) const;
    // Runs `sql` (no result) in database `db` as the admin role.
    void Sql(const std::string& db, const std::string& sql) const;
    // The first column of the first row of `sql` in `db`, as text ("" when no row or NULL).
    std::string Query(const std::string& db, const std::string& sql) const;
    // A login role with a password (created once per server; the same password every time).
    void EnsureRole(const std::string& role, const std::string& password) const;

    static constexpr const char* kAdmin = "gyroadmin";
    static constexpr const char* kAdminPassword = "admin-pw-7f3c";
    static constexpr int kPort = 5432;  // names the socket file only: nothing listens on TCP

private:
    explicit PgServer(std::string dir) : dir_(std::move(dir)) {}
    void StartExisting();
    std::string dir_;
    bool owned_ = false, durable_ = false;
    int tcp_port_ = 0;
    std::string tls_dir_;
};

// The server of this test process: the CTest fixture's, or one started for it.
PgServer& SharedPgServer();

// Runs `command` (via /bin/sh); as the user 'postgres' when this process is root. Returns its
// exit status.
int RunAsServerUser(const std::string& command);

}  // namespace gyrocal::testing
