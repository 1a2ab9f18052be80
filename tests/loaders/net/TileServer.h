// tile_server.py (tests/loaders/net) run by a test as a local HTTP server on 127.0.0.1, well-behaved or not by path.
#pragma once
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

extern char** environ;

namespace testutil {

// tile_server.py serving `dir`, as a child process: its stdout read through a pipe (the port, then "arrived"
// lines), its stdin a pipe whose closing (this process gone, however) ends it. With a certificate and its key (PEM
// files), over HTTPS.
class TileServer {
public:
    explicit TileServer(const std::string& dir, const std::string& tlsCert = "", const std::string& tlsKey = "")
        : scheme_(tlsCert.empty() ? "http" : "https") {
        int out[2], in[2];
        if (::pipe2(out, O_CLOEXEC) != 0) throw std::runtime_error("pipe");
        if (::pipe2(in, O_CLOEXEC) != 0) {
            ::close(out[0]), ::close(out[1]);
            throw std::runtime_error("pipe");
        }
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_adddup2(&actions, in[0], 0);
        posix_spawn_file_actions_adddup2(&actions, out[1], 1);
        std::vector<const char*> argv = {"python3", SGKIT_TILE_SERVER, dir.c_str()};
        if (!tlsCert.empty()) argv.insert(argv.end(), {"--tls", tlsCert.c_str(), tlsKey.c_str()});
        argv.push_back(nullptr);
        const int rc =
            posix_spawnp(&pid_, "python3", &actions, nullptr, const_cast<char* const*>(argv.data()), environ);
        posix_spawn_file_actions_destroy(&actions);
        ::close(in[0]);
        ::close(out[1]);
        out_ = out[0];
        in_ = in[1];
        if (rc != 0) {
            pid_ = -1;
            throw std::runtime_error(std::string("cannot run python3: ") + std::strerror(rc));
        }
        const std::string line = readLine();
        port_ = std::atoi(line.c_str());
        if (port_ <= 0) throw std::runtime_error("tile_server.py printed no port (\"" + line + "\")");
    }
    ~TileServer() {
        if (pid_ > 0) {
            ::kill(pid_, SIGKILL);
            int status = 0;
            while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
            }
        }
        if (out_ >= 0) ::close(out_);
        if (in_ >= 0) ::close(in_);
    }
    TileServer(const TileServer&) = delete;
    TileServer& operator=(const TileServer&) = delete;

    std::string url(const std::string& path) const { return scheme_ + "://127.0.0.1:" + std::to_string(port_) + path; }

    // The next line of the server's stdout; "" when it closes or says nothing for a minute (a broken server must
    // fail a test, not hang it).
    std::string readLine() {
        for (;;) {
            const size_t nl = buffered_.find('\n');
            if (nl != std::string::npos) {
                std::string line = buffered_.substr(0, nl);
                buffered_.erase(0, nl + 1);
                return line;
            }
            pollfd p{out_, POLLIN, 0};
            if (::poll(&p, 1, 60000) <= 0) return "";
            char buf[256];
            const ssize_t n = ::read(out_, buf, sizeof buf);
            if (n <= 0) return "";
            buffered_.append(buf, size_t(n));
        }
    }

private:
    std::string scheme_;
    pid_t pid_ = -1;
    int out_ = -1, in_ = -1, port_ = 0;
    std::string buffered_;
};

}  // namespace testutil
