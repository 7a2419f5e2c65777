// pg-test-server: a throwaway PostgreSQL 15 (pg_test_server.hpp) for tests that are not C++
// (the browser tests). Prints "conninfo host=127.0.0.1 port=N user=postgres dbname=lab" once
// the server takes connections, then runs until its standard input closes, and tears the
// server down (and deletes it) on the way out.
#include <csignal>
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>

#include "pg_test_server.hpp"

int main() {
  std::signal(SIGPIPE, SIG_IGN);
  try {
    rig::testing::PgTestServer server;
    std::cout << "conninfo " << server.conninfo() << std::endl;
    std::string line;
    while (std::getline(std::cin, line)) {
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "pg-test-server: " << e.what() << "\n";
    return 1;
  }
}
