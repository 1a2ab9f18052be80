// Debian's nginx run by a test as the web server users serve tiles with: a child process on a free port of
// 127.0.0.1, its own configuration and files in a temporary directory, its access log read back by the test.
#pragma once
#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace testutil {

struct NginxConfig {
    std::string root;              // the directory served
    std::string cert, key;         // PEM files: HTTPS with HTTP/2 ("listen ... ssl http2") when both are given;
                                   // else plain HTTP/1.1
    bool gzip = true;              // gzip on, every type (gzip_types *), gzip_min_length 256
    int keepaliveRequests = 1000;  // keepalive_requests
    std::string extra;             // more directives inside server { }, e.g.
                                   // "location /fresh/ { add_header Cache-Control \"max-age=3600\"; }"
};

struct NginxLogLine {         // one finished request, from the access log
    std::string method, uri;  // uri: $request_uri, with its query
    int status = 0;
    uint64_t connection = 0;          // $connection: the connection's serial number
    uint64_t connectionRequests = 0;  // $connection_requests
    std::string protocol;             // $server_protocol: "HTTP/1.1", "HTTP/2.0"
    uint64_t bodyBytes = 0;           // $body_bytes_sent (as sent: compressed when gzipped)
    std::string ifNoneMatch, ifModifiedSince, authorization, acceptEncoding;  // request headers; "" if absent
};

// nginx serving config.root. The process stays in the foreground as one process (master_process off: no worker
// drops to `nobody`, who could not read a test's files), and dies with the thread that started it (PDEATHSIG), so
// a test that crashes leaves none behind. nginx writes a request's log line just after its response is sent: a
// test that reads log() right after a read waits for the line it expects.
class Nginx {
public:
    explicit Nginx(NginxConfig config) : config_(std::move(config)) {
        const std::string exe = findNginx();
        std::string pattern = (std::filesystem::temp_directory_path() / "sgkit-nginx-XXXXXX").string();
        if (!::mkdtemp(pattern.data())) throw std::runtime_error("Nginx: cannot make a temporary directory");
        dir_ = pattern;
        std::string why;
        try {
            // A port found free can be taken by another process before nginx binds it: then another one.
            for (int attempt = 0; attempt < 3; ++attempt) {
                port_ = freePort();
                if (start(exe, why)) return;
                if (why.find("Address already in use") == std::string::npos) break;
            }
        } catch (...) {
            removeDir();
            throw;
        }
        removeDir();
        throw std::runtime_error("Nginx: nginx could not start: " + why);
    }
    ~Nginx() {
        stop();
        removeDir();
    }
    Nginx(const Nginx&) = delete;
    Nginx& operator=(const Nginx&) = delete;

    std::string url(const std::string& path) const {
        return std::string(tls() ? "https" : "http") + "://127.0.0.1:" + std::to_string(port_) + path;
    }
    int port() const { return port_; }

    // The access log so far, in order (a line still being written left out).
    // The access log once it holds `count` requests at least: nginx writes a request's line just after its response
    // has gone, so a client that has read the response can be a moment ahead of it. 10 s is a failure guard only
    // (a request never made never comes).
    std::vector<NginxLogLine> logAtLeast(size_t count) const {
        const auto guard = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        std::vector<NginxLogLine> lines = log();
        while (lines.size() < count && std::chrono::steady_clock::now() < guard) {
            ::poll(nullptr, 0, 5);
            lines = log();
        }
        return lines;
    }

    std::vector<NginxLogLine> log() const {
        std::ifstream in(dir_ + "/access.log", std::ios::binary);
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        std::vector<NginxLogLine> lines;
        size_t start = 0;
        for (size_t nl; (nl = text.find('\n', start)) != std::string::npos; start = nl + 1) {
            const std::vector<std::string> f = split(text.substr(start, nl - start));
            if (f.size() != 11) continue;
            NginxLogLine l;
            l.method = f[0];
            l.uri = f[1];
            l.status = int(number(f[2]));
            l.connection = number(f[3]);
            l.connectionRequests = number(f[4]);
            l.protocol = f[5];
            l.bodyBytes = number(f[6]);
            l.ifNoneMatch = f[7];
            l.ifModifiedSince = f[8];
            l.authorization = f[9];
            l.acceptEncoding = f[10];
            lines.push_back(std::move(l));
        }
        return lines;
    }

private:
    bool tls() const { return !config_.cert.empty() && !config_.key.empty(); }

    // Where Debian puts nginx (/usr/sbin is not on a user's PATH), else PATH.
    static std::string findNginx() {
        std::vector<std::string> dirs;
        if (const char* p = std::getenv("PATH")) {
            std::stringstream s(p);
            for (std::string d; std::getline(s, d, ':');)
                if (!d.empty()) dirs.push_back(d);
        }
        dirs.insert(dirs.end(), {"/usr/sbin", "/usr/local/sbin", "/sbin"});
        for (const std::string& d : dirs)
            if (::access((d + "/nginx").c_str(), X_OK) == 0) return d + "/nginx";
        throw std::runtime_error("Nginx: no nginx on PATH nor in /usr/sbin (Debian's package nginx)");
    }

    // A port the system calls free now (bound to port 0, read back, closed).
    static int freePort() {
        const int s = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
        if (s < 0) throw std::runtime_error("Nginx: socket() failed");
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        socklen_t n = sizeof a;
        const bool ok = ::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0 &&
                        ::getsockname(s, reinterpret_cast<sockaddr*>(&a), &n) == 0;
        ::close(s);
        if (!ok) throw std::runtime_error("Nginx: no free port on 127.0.0.1");
        return ntohs(a.sin_port);
    }

    bool accepts() const {
        const int s = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
        if (s < 0) return false;
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        a.sin_port = htons(uint16_t(port_));
        const bool ok = ::connect(s, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
        ::close(s);
        return ok;
    }

    // A path as an nginx string: quoted, with its quotes and backslashes escaped.
    static std::string quoted(const std::string& s) {
        std::string q = "\"";
        for (char c : s) q += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
        return q + "\"";
    }

    std::string configText() const {
        const std::string d = dir_ + "/";
        std::ostringstream c;
        c << "master_process off;\nerror_log " << quoted(d + "error.log") << ";\npid " << quoted(d + "nginx.pid")
          << ";\nevents { worker_connections 1024; }\nhttp {\n"
          << "  include /etc/nginx/mime.types;\n  default_type application/octet-stream;\n"
          // Tab-separated, unescaped (an ETag's quotes as sent); an empty field is "-".
          << "  log_format sg escape=none '$request_method\\t$request_uri\\t$status\\t$connection\\t"
          << "$connection_requests\\t$server_protocol\\t$body_bytes_sent\\t$http_if_none_match\\t"
          << "$http_if_modified_since\\t$http_authorization\\t$http_accept_encoding';\n"
          << "  access_log " << quoted(d + "access.log") << " sg;\n";
        for (const char* t : {"client_body", "proxy", "fastcgi", "uwsgi", "scgi"})
            c << "  " << t << "_temp_path " << quoted(d + t) << ";\n";
        c << "  sendfile on;\n  etag on;\n  keepalive_timeout 60s;\n"
          << "  keepalive_requests " << config_.keepaliveRequests << ";\n";
        if (config_.gzip)
            c << "  gzip on;\n  gzip_types *;\n  gzip_proxied any;\n  gzip_vary on;\n  gzip_min_length 256;\n";
        else
            c << "  gzip off;\n";
        c << "  server {\n    listen 127.0.0.1:" << port_ << (tls() ? " ssl http2" : "") << ";\n";
        if (tls())
            c << "    ssl_certificate " << quoted(config_.cert) << ";\n    ssl_certificate_key " << quoted(config_.key)
              << ";\n";
        const std::string root = std::filesystem::absolute(config_.root).string();
        c << "    root " << quoted(root) << ";\n    " << config_.extra << "\n  }\n}\n";
        return c.str();
    }

    // nginx on port_, waited for: true when it accepts connections; false (why: its errors) when it exited.
    bool start(const std::string& exe, std::string& why) {
        std::filesystem::remove(dir_ + "/error.log");
        std::filesystem::remove(dir_ + "/stderr.log");
        std::ofstream(dir_ + "/nginx.conf") << configText();
        const std::string conf = dir_ + "/nginx.conf", errFile = dir_ + "/stderr.log";
        const char* argv[] = {exe.c_str(), "-p", dir_.c_str(), "-c", conf.c_str(), "-g", "daemon off;", nullptr};
        const pid_t parent = ::getpid();
        pid_ = ::fork();
        if (pid_ < 0) throw std::runtime_error("Nginx: fork() failed");
        if (pid_ == 0) {  // only async-signal-safe calls until exec
            ::prctl(PR_SET_PDEATHSIG, SIGKILL);
            if (::getppid() != parent) ::_exit(127);
            const int err = ::open(errFile.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
            if (err >= 0) ::dup2(err, 1), ::dup2(err, 2);
            ::execv(exe.c_str(), const_cast<char* const*>(argv));
            ::_exit(127);
        }
        const auto guard = std::chrono::steady_clock::now() + std::chrono::seconds(30);
        for (;;) {
            int status = 0;
            if (::waitpid(pid_, &status, WNOHANG) == pid_) {
                pid_ = -1;
                why = errors();
                return false;
            }
            if (pidFileIsOurs() && accepts()) return true;
            if (std::chrono::steady_clock::now() > guard) {
                stop();
                why = "not accepting connections after 30 s; " + errors();
                return false;
            }
            ::poll(nullptr, 0, 5);  // the next look at a child that is starting
        }
    }

    // nginx writes its pid file once its sockets listen: a connection then is to this nginx, not another process
    // that took the port.
    bool pidFileIsOurs() const {
        std::ifstream in(dir_ + "/nginx.pid");
        long pid = 0;
        return (in >> pid) && pid == long(pid_);
    }

    std::string errors() const {
        for (const char* f : {"/stderr.log", "/error.log"}) {
            std::ifstream in(dir_ + f);
            const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
            if (!text.empty()) return text;
        }
        return "(nothing in its error log)";
    }

    void stop() {
        if (pid_ <= 0) return;
        ::kill(pid_, SIGTERM);  // fast shutdown: open connections closed
        const auto guard = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        int status = 0;
        for (;;) {
            const pid_t r = ::waitpid(pid_, &status, WNOHANG);
            if (r == pid_ || (r < 0 && errno != EINTR)) break;
            if (std::chrono::steady_clock::now() > guard) {
                ::kill(pid_, SIGKILL);
                while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
                }
                break;
            }
            ::poll(nullptr, 0, 5);
        }
        pid_ = -1;
    }

    void removeDir() {
        std::error_code ec;
        if (!dir_.empty()) std::filesystem::remove_all(dir_, ec);
    }

    static std::vector<std::string> split(const std::string& line) {
        std::vector<std::string> f;
        size_t start = 0;
        for (size_t tab;; start = tab + 1) {
            tab = line.find('\t', start);
            const std::string field = line.substr(start, tab == std::string::npos ? tab : tab - start);
            f.push_back(field == "-" ? "" : field);
            if (tab == std::string::npos) return f;
        }
    }

    static uint64_t number(const std::string& s) { return std::strtoull(s.c_str(), nullptr, 10); }

    NginxConfig config_;
    std::string dir_;
    pid_t pid_ = -1;
    int port_ = 0;
};

}  // namespace testutil
