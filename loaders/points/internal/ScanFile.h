// A scan file opened for reading at offsets: regular files only, opened without waiting (a FIFO is refused, not
// waited on), every read checked. Internal header (an internal/ folder): not installed.
#pragma once
#include "loaders/gltf/Gltf.h"  // sg::LoadError

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <string>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace sg {

class ScanFile {
public:
    explicit ScanFile(const std::string& path) : path_(path) {
        // Non-blocking: opening a FIFO must not wait for a writer (it is then refused as not regular).
        fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
        if (fd_ < 0) throw LoadError(path, "", std::string("cannot open: ") + std::strerror(errno));
        struct stat st {};
        if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
            ::close(fd_);
            throw LoadError(path, "", "not a regular file");
        }
        size_ = uint64_t(st.st_size);
    }
    ~ScanFile() { ::close(fd_); }
    ScanFile(const ScanFile&) = delete;
    ScanFile& operator=(const ScanFile&) = delete;

    const std::string& path() const { return path_; }
    uint64_t size() const { return size_; }

    // Exactly `n` bytes at `offset`, or a LoadError naming the offset (the file may have shrunk since it was opened).
    void readAt(uint64_t offset, void* out, size_t n) const {
        auto* p = static_cast<unsigned char*>(out);
        while (n > 0) {
            const ssize_t got = ::pread(fd_, p, n, off_t(offset));
            if (got < 0 && errno == EINTR) continue;
            if (got < 0) throw LoadError(path_, "offset " + std::to_string(offset), std::strerror(errno));
            if (got == 0) throw LoadError(path_, "offset " + std::to_string(offset), "truncated: the file ends here");
            p += got;
            n -= size_t(got);
            offset += uint64_t(got);
        }
    }

private:
    std::string path_;
    int fd_ = -1;
    uint64_t size_ = 0;
};

}  // namespace sg
