// The CTest fixture `central_pg` (tests/store/CMakeLists.txt): `pg_test_server start DIR` starts
// the throwaway PostgreSQL server the central tests share, `pg_test_server stop DIR` stops it and
// removes DIR. Exit 0 on success, 1 with the reason on stderr.
#include <filesystem>
#include <iostream>
#include <string>

#include "tests/store/pg_server.hpp"

int main(int argc, char** argv) {
    using gyrocal::testing::PgServer;
    if (argc != 3) {
        std::cerr << "usage: pg_test_server start|stop DIR\n";
        return 2;
    }
    const std::string what = argv[1], dir = argv[2];
    try {
        if (what == "start") {
            if (auto running = PgServer::Attach(dir)) running->Stop();  // left by a crashed run
            PgServer::Start(dir)->Detach();
            std::cout << "pg_test_server: started in " << dir << "\n";
            return 0;
        }
        if (what == "stop") {
            if (auto running = PgServer::Attach(dir)) running->Stop();
            std::error_code ec;
            std::filesystem::remove_all(dir, ec);
            std::cout << "pg_test_server: stopped, " << dir << " removed\n";
            return 0;
        }
    } catch (const std::exception& e) {
        std::cerr << "pg_test_server: " << e.what() << "\n";
        return 1;
    }
    std::cerr << "usage: pg_test_server start|stop DIR\n";
    return 2;
}
