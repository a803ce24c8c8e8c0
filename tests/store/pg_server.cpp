#include "tests/store/pg_server.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <pwd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <pqxx/pqxx>
#include <sstream>
#include <stdexcept>

namespace gyrocal::testing {
namespace fs = std::filesystem;
namespace {

// The newest installed server's programs (Debian: /usr/lib/postgresql/<major>/bin).
std::string BinDir() {
    std::string best;
    int best_major = -1;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator("/usr/lib/postgresql", ec)) {
        const int major = std::atoi(e.path().filename().c_str());
        if (major > best_major && fs::exists(e.path() / "bin" / "initdb")) {
            best_major = major;
            best = (e.path() / "bin").string();
        }
    }
    if (best.empty())
        throw std::runtime_error("no PostgreSQL server installed (apt-get install postgresql)");
    return best;
}

std::string Quoted(const std::string& s) {
    std::string out = "'";
    for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

std::string FileText(const fs::path& p) {
    std::ifstream f(p);
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
}

// Makes `p` the server user's when this process is root (the server refuses to run as root).
void GiveToServerUser(const fs::path& p) {
    if (geteuid() != 0) return;
    const passwd* pw = getpwnam("postgres");
    if (pw == nullptr)
        throw std::runtime_error(
            "running as root and there is no user 'postgres' to run the "
            "server as (apt-get install postgresql creates it)");
    if (chown(p.c_str(), pw->pw_uid, pw->pw_gid) != 0)
        throw std::runtime_error("cannot chown " + p.string() + " to postgres");
}

}  // namespace

int RunAsServerUser(const std::string& command) {
    const std::string cmd =
        geteuid() == 0 ? "runuser -u postgres -- /bin/sh -c " + Quoted(command) : command;
    const int rc = std::system(cmd.c_str());
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : 128;
}

// A TCP port nothing listens on now (the kernel's choice).
int FreePort() {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof a;
    if (fd < 0 || bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
        getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) != 0)
        throw std::runtime_error("no free TCP port on 127.0.0.1");
    const int port = ntohs(a.sin_port);
    close(fd);
    return port;
}

std::unique_ptr<PgServer> PgServer::StartWithTls(const std::string& dir) {
    auto s = Start(dir);
    s->Stop();
    const std::string tls = dir + "/tls";
    fs::create_directories(tls);
    GiveToServerUser(tls);
    if (RunAsServerUser("openssl req -x509 -newkey rsa:2048 -nodes -days 1 -subj /CN=localhost "
                        "-keyout " +
                        tls + "/server.key -out " + tls + "/server.crt > " + tls +
                        "/openssl.log 2>&1 && chmod 600 " + tls + "/server.key") != 0)
        throw std::runtime_error("openssl could not make a certificate: " +
                                 FileText(fs::path(tls) / "openssl.log"));
    s->tcp_port_ = FreePort();
    s->tls_dir_ = tls;
    s->StartExisting();
    return s;
}

std::unique_ptr<PgServer> PgServer::Start(const std::string& dir, bool durable) {
    std::error_code ec;
    fs::remove_all(dir, ec);
    fs::create_directories(dir);
    GiveToServerUser(dir);
    { std::ofstream(fs::path(dir) / "pw") << kAdminPassword << "\n"; }
    GiveToServerUser(fs::path(dir) / "pw");
    const std::string init = BinDir() + "/initdb -D " + dir + "/data -U " + kAdmin +
                             " --pwfile=" + dir + "/pw -A scram-sha-256 -E UTF8 --no-locale -N > " +
                             dir + "/initdb.log 2>&1";
    if (RunAsServerUser(init) != 0)
        throw std::runtime_error("initdb failed: " + FileText(fs::path(dir) / "initdb.log"));
    std::unique_ptr<PgServer> s(new PgServer(dir));
    s->owned_ = true;
    s->durable_ = durable;
    s->StartExisting();
    return s;
}

std::unique_ptr<PgServer> PgServer::Attach(const std::string& dir) {
    std::unique_ptr<PgServer> s(new PgServer(dir));
    if (!s->Running()) return nullptr;
    return s;
}

void PgServer::StartExisting() {
    std::string opts = "-k " + dir_ + " -c listen_addresses='' -p " + std::to_string(kPort) +
                       (durable_ ? "" : " -c fsync=off -c full_page_writes=off") +
                       " -c max_connections=200";
    if (tcp_port_ > 0) {  // also on 127.0.0.1 with TLS (the socket file is named by the port)
        opts = "-k " + dir_ + " -c listen_addresses=127.0.0.1 -p " + std::to_string(tcp_port_) +
               " -c fsync=off -c ssl=on -c ssl_cert_file=" + tls_dir_ + "/server.crt" +
               " -c ssl_key_file=" + tls_dir_ + "/server.key";
    }
    const std::string cmd = BinDir() + "/pg_ctl -D " + dir_ + "/data -l " + dir_ +
                            "/server.log -w -t 60 -o " + Quoted(opts) + " start > " + dir_ +
                            "/pg_ctl.log 2>&1";
    if (RunAsServerUser(cmd) != 0)
        throw std::runtime_error("the test PostgreSQL server did not start: " +
                                 FileText(fs::path(dir_) / "server.log"));
}

bool PgServer::Running() const {
    if (!fs::exists(fs::path(dir_) / "data" / "postmaster.pid")) return false;
    const std::string cmd = BinDir() + "/pg_isready -q -h " + dir_ + " -p " +
                            std::to_string(tcp_port_ ? tcp_port_ : kPort) + " > /dev/null 2>&1";
    return std::system(cmd.c_str()) == 0;
}

void PgServer::Stop() {
    RunAsServerUser(BinDir() + "/pg_ctl -D " + dir_ +
                    "/data -m immediate -w stop > /dev/null 2>&1");
}

void PgServer::Restart() {
    Stop();
    StartExisting();
}

PgServer::~PgServer() {
    if (!owned_) return;
    Stop();
    std::error_code ec;
    fs::remove_all(dir_, ec);
}

std::string PgServer::Url(const std::string& db, const std::string& user,
                          const std::string& password) const {
    return "postgresql://" + user + (password.empty() ? "" : ":" + password) + "@/" + db +
           "?host=" + dir_ + "&port=" + std::to_string(tcp_port_ ? tcp_port_ : kPort);
}

std::string PgServer::NewDatabase(const std::string& prefix) const {
    static std::atomic<int> counter{0};
    const std::string name =
        prefix + "_" + std::to_string(getpid()) + "_" + std::to_string(++counter);
    pqxx::connection c(Url("postgres"));
    pqxx::nontransaction tx(c);
    tx.exec("CREATE DATABASE " + tx.quote_name(name));
    return name;
}

void PgServer::Sql(const std::string& db, const std::string& sql) const {
    pqxx::connection c(Url(db));
    pqxx::nontransaction tx(c);
    tx.exec(sql);
}

std::string PgServer::Query(const std::string& db, const std::string& sql) const {
    pqxx::connection c(Url(db));
    pqxx::nontransaction tx(c);
    const pqxx::result r = tx.exec(sql);
    return r.empty() || r[0][0].is_null() ? std::string() : std::string(r[0][0].c_str());
}

void PgServer::EnsureRole(const std::string& role, const std::string& password) const {
    pqxx::connection c(Url("postgres"));
    pqxx::nontransaction tx(c);
    try {
        tx.exec("CREATE ROLE " + tx.quote_name(role) + " LOGIN PASSWORD " + tx.quote(password));
    } catch (const pqxx::sql_error& e) {
        // Another test process made it first (42710 duplicate_object; 23505 when both at once).
        if (e.sqlstate() != "42710" && e.sqlstate() != "23505") throw;
    }
}

PgServer& SharedPgServer() {
    static std::unique_ptr<PgServer> server = [] {
        if (const char* dir = std::getenv("GYROCAL_TEST_PG_DIR"); dir && *dir) {
            if (auto s = PgServer::Attach(dir)) return s;
        }
        char tmpl[] = "/tmp/gyrocal-pg-XXXXXX";
        if (mkdtemp(tmpl) == nullptr) throw std::runtime_error("mkdtemp failed");
        return PgServer::Start(tmpl);
    }();
    return *server;
}

}  // namespace gyrocal::testing
