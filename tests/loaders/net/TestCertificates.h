// A certificate authority of a test's own and the server certificates it signs, made with Debian's openssl: one
// for 127.0.0.1, one for another name, one expired; PEM files in a directory of the test's.
#pragma once
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <utility>

namespace testutil {

struct TestCertificates {
    std::string dir;  // holds ca.pem and, for each certificate NAME, NAME.pem and its key NAME.key

    // Made in `directory` (which exists); throws std::runtime_error with openssl's output when it cannot.
    explicit TestCertificates(std::string directory) : dir(std::move(directory)) {
        const std::string ec = " -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes";
        // A past validity cannot be given to `openssl x509 -req` (-days counts from now): `openssl ca` takes
        // dates, with a database of its own.
        std::ofstream(dir + "/ca.cnf") << "[ca]\ndefault_ca = test\n[test]\ndatabase = index.txt\nserial = serial\n"
                                          "new_certs_dir = .\ndefault_md = sha256\npolicy = any\n"
                                          "copy_extensions = copy\nunique_subject = no\n[any]\ncommonName = supplied\n";
        std::ofstream(dir + "/index.txt");
        std::ofstream(dir + "/serial") << "01\n";
        const std::string sign =
            "openssl x509 -req -CA ca.pem -CAkey ca.key -CAcreateserial -days 2 "
            "-copy_extensions copy";
        run("openssl req -x509" + ec + " -days 2 -subj '/CN=sgkit test authority' -keyout ca.key -out ca.pem");
        run("openssl req -new" + ec + " -subj /CN=127.0.0.1 -addext subjectAltName=IP:127.0.0.1,DNS:localhost " +
            "-keyout good.key -out good.csr");
        run(sign + " -in good.csr -out good.pem");
        run("openssl req -new" + ec + " -subj /CN=example.org -addext subjectAltName=DNS:example.org " +
            "-keyout other.key -out other.csr");
        run(sign + " -in other.csr -out other.pem");
        run("openssl ca -batch -config ca.cnf -cert ca.pem -keyfile ca.key -notext -in good.csr -out expired.pem "
            "-startdate 20200101000000Z -enddate 20200102000000Z");
        run("cp good.key expired.key");
    }

    std::string ca() const { return dir + "/ca.pem"; }
    // "good": 127.0.0.1 (and localhost), valid; "other": example.org only; "expired": 127.0.0.1, ended in 2020.
    std::string cert(const std::string& name) const { return dir + "/" + name + ".pem"; }
    std::string key(const std::string& name) const { return dir + "/" + name + ".key"; }

private:
    void run(const std::string& command) const {
        const std::string log = dir + "/openssl.log";
        if (std::system(("cd '" + dir + "' && " + command + " > '" + log + "' 2>&1").c_str()) == 0) return;
        std::ifstream in(log);
        const std::string out((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        throw std::runtime_error("openssl failed: " + command + "\n" + out);
    }
};

}  // namespace testutil
