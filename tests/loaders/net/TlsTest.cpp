// https against Debian's nginx with certificates the test makes (its own authority): trusted through
// ResourceOptions::caFile and read over HTTP/2; refused, the reason naming the certificate's problem, when its
// authority is not trusted, its name is another's or it has expired; a caFile that cannot be used named as such;
// a tileset read over https.
#include "loaders/net/Nginx.h"
#include "loaders/net/Resource.h"
#include "loaders/net/TestCertificates.h"
#include "loaders/tiles/Tileset.h"
#include "loaders/tiles/TilesetTestUtil.h"

#include <gtest/gtest.h>
#include <poll.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

using namespace sg;
namespace fs = std::filesystem;
using testutil::Nginx;
using testutil::NginxLogLine;
using tilestest::errorOf;

namespace {

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// The served files (a one-tile tileset) and the certificates, made once for the suite.
class Tls : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        files_ = new std::string((fs::temp_directory_path() / ("sgkit-tls-" + std::to_string(::getpid()))).string());
        fs::remove_all(*files_);
        fs::create_directories(file("www"));
        fs::create_directories(file("certs"));
        tilestest::writeBoxTileset(file("www"));
        try {
            certs_ = new testutil::TestCertificates(file("certs"));
        } catch (const std::exception& e) {
            failure_ = new std::string(e.what());
        }
    }
    static void TearDownTestSuite() {
        fs::remove_all(*files_);
        delete certs_;
        delete failure_;
        delete files_;
        certs_ = nullptr, failure_ = nullptr, files_ = nullptr;
    }
    void SetUp() override { ASSERT_TRUE(certs_) << *failure_; }

    static std::string file(const std::string& name) { return *files_ + "/" + name; }

    // nginx serving the tileset with the certificate `name` ("good", "other", "expired").
    static std::unique_ptr<Nginx> serve(const std::string& name) {
        testutil::NginxConfig c;
        c.root = file("www");
        c.cert = certs_->cert(name);
        c.key = certs_->key(name);
        return std::make_unique<Nginx>(c);
    }
    static ResourceOptions trusting() {
        ResourceOptions o;
        o.caFile = certs_->ca();
        return o;
    }

    static std::string* files_;  // the suite's directory
    static testutil::TestCertificates* certs_;
    static std::string* failure_;
};
std::string* Tls::files_ = nullptr;
testutil::TestCertificates* Tls::certs_ = nullptr;
std::string* Tls::failure_ = nullptr;

}  // namespace

TEST_F(Tls, ACertificateOfATrustedAuthorityIsReadOverHttp2) {
    const auto server = serve("good");
    EXPECT_EQ(readResource(server->url("/tileset.json"), trusting()), readResource(file("www/tileset.json")));
    const std::vector<NginxLogLine> log = server->logAtLeast(1);
    ASSERT_EQ(log.size(), 1u);
    EXPECT_EQ(log[0].uri, "/tileset.json");
    EXPECT_EQ(log[0].status, 200);
    EXPECT_EQ(log[0].protocol, "HTTP/2.0");
}

TEST_F(Tls, AnAuthorityNotTrustedIsRefusedNamingTheCertificate) {
    const auto server = serve("good");
    const std::string url = server->url("/tileset.json");
    const LoadError e = errorOf([&] { readResource(url); });  // the system's authorities: not the test's
    EXPECT_EQ(e.file(), url);
    EXPECT_TRUE(has(e.reason(), "the server's certificate is not trusted")) << e.what();
    EXPECT_TRUE(has(e.reason(), "unable to get local issuer certificate")) << e.what();
    EXPECT_TRUE(server->log().empty());  // refused before a request was sent
}

TEST_F(Tls, ACertificateForAnotherNameIsRefusedNamingTheName) {
    const auto server = serve("other");  // example.org's, served at 127.0.0.1
    const LoadError e = errorOf([&] { readResource(server->url("/tileset.json"), trusting()); });
    EXPECT_TRUE(has(e.reason(), "the server's certificate is not trusted")) << e.what();
    EXPECT_TRUE(has(e.reason(), "host name '127.0.0.1'")) << e.what();
}

TEST_F(Tls, AnExpiredCertificateIsRefusedSayingSo) {
    const auto server = serve("expired");
    const LoadError e = errorOf([&] { readResource(server->url("/tileset.json"), trusting()); });
    EXPECT_TRUE(has(e.reason(), "the server's certificate is not trusted")) << e.what();
    EXPECT_TRUE(has(e.reason(), "expired")) << e.what();
}

TEST_F(Tls, ACaFileThatCannotBeUsedIsNamed) {
    const auto server = serve("good");
    ResourceOptions missing;
    missing.caFile = file("none.pem");
    const LoadError gone = errorOf([&] { readResource(server->url("/tileset.json"), missing); });
    EXPECT_TRUE(has(gone.reason(), "the certificate authorities file '" + missing.caFile + "' cannot be used"))
        << gone.what();
    EXPECT_TRUE(has(gone.reason(), "No such file")) << gone.what();

    ResourceOptions notPem;
    notPem.caFile = file("www/tileset.json");
    const LoadError bad = errorOf([&] { readResource(server->url("/tileset.json"), notPem); });
    EXPECT_TRUE(has(bad.reason(), "'" + notPem.caFile + "' cannot be used: it holds no PEM certificate")) << bad.what();
}

// A tileset over https: its root's content read through the same options; without the authority, refused.
TEST_F(Tls, ATilesetIsReadOverHttps) {
    const auto server = serve("good");
    TilesetOptions o;
    o.resource = trusting();
    const Tileset ts = loadTileset(server->url("/tileset.json"), o);
    EXPECT_EQ(ts.counts().tiles, 1u);
    EXPECT_EQ(ts.counts().contents, 1u);
    const std::vector<NginxLogLine> log = server->logAtLeast(2);
    ASSERT_EQ(log.size(), 2u);
    EXPECT_EQ(log[1].uri, "/box.glb");
    EXPECT_EQ(log[1].status, 200);
    EXPECT_EQ(log[1].protocol, "HTTP/2.0");

    const LoadError e = errorOf([&] { loadTileset(server->url("/tileset.json")); });
    EXPECT_TRUE(has(e.reason(), "certificate")) << e.what();
}
