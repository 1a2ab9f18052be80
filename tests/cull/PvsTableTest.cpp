// PvsTable: the grid's cells, the bits, the binding to one image, and the file (round trip, corrupt files).
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "sg/cull/PvsTable.h"
#include "sg/scene/Scene.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>

using namespace sg;

namespace {
ref_ptr<Group> boxes(int n) {
    auto root = make<Group>();
    for (int k = 0; k < n; ++k)
        root->addChild(make<Geometry>(makeBoxMesh(dvec3(k, 0, 0), dvec3(k + 0.5, 1, 1)), make<Material>()));
    return root;
}

PvsTable::Grid grid() {
    PvsTable::Grid g;
    g.origin = dvec3(-10, 0, 1);
    g.cellSize = dvec3(2, 5, 1);
    g.nx = 10;
    g.ny = 4;
    g.nz = 2;
    return g;
}

std::string bytesOf(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
}
void writeBytes(const std::string& path, const std::string& b) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(b.data(), std::streamsize(b.size()));
}
// load() must throw std::runtime_error naming the file and containing `what`.
void expectLoadFails(const std::string& path, const std::string& what) {
    try {
        PvsTable::load(path);
        FAIL() << "loaded a corrupt file (" << what << ")";
    } catch (const std::runtime_error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("PvsTable::load(): " + path), std::string::npos) << m;
        EXPECT_NE(m.find(what), std::string::npos) << m;
    }
}
// Header offsets: magic 0, version 8, entries 12, hash 16, nx 24, ny 28, nz 32, origin 36, cell size 60,
// near range 84, words per cell 100; bits from 108.
template <class T>
void poke(std::string& b, size_t at, T v) {
    std::memcpy(&b[at], &v, sizeof v);
}
}  // namespace

TEST(PvsTable, CellsCoverTheGridAndNothingElse) {
    Scene s(boxes(3));
    s.update();
    const PvsTable t(grid(), s.image(), 0.1, 1.0);
    EXPECT_EQ(t.cellCount(), 80u);
    EXPECT_EQ(t.cellAt(dvec3(-10, 0, 1)), 0);
    EXPECT_EQ(t.cellAt(dvec3(-9.5, 6, 1.5)), 0 + 10 * 1);
    EXPECT_EQ(t.cellAt(dvec3(10, 20, 3)), 79);  // the far corner belongs to the last cell
    EXPECT_EQ(t.cellAt(dvec3(10.001, 20, 3)), -1);
    EXPECT_EQ(t.cellAt(dvec3(-10.001, 1, 1)), -1);
    EXPECT_EQ(t.cellAt(dvec3(0, 1, 0.5)), -1);
    EXPECT_EQ(t.cellAt(dvec3(std::nan(""), 1, 1)), -1);
    for (size_t c : {size_t(0), size_t(37), size_t(79)}) {
        const Box b = t.cellBox(c);
        EXPECT_EQ(t.cellAt(b.center()), long(c));
        EXPECT_TRUE(b.contains(b.center()));
    }
    EXPECT_EQ(t.hiddenFor(dvec3(100, 0, 0)), nullptr);
    EXPECT_NE(t.hiddenFor(dvec3(0, 1, 1.5)), nullptr);
}

TEST(PvsTable, BitsPerCell) {
    Scene s(boxes(70));  // 71 entries: two words per cell
    s.update();
    PvsTable t(grid(), s.image(), 0.1, 1.0);
    EXPECT_EQ(t.entryCount(), 71u);
    EXPECT_EQ(t.wordsPerCell(), 2u);
    t.setHidden(5, 3);
    t.setHidden(5, 70);
    t.setHidden(6, 64);
    EXPECT_TRUE(t.isHidden(5, 3));
    EXPECT_TRUE(t.isHidden(5, 70));
    EXPECT_FALSE(t.isHidden(5, 64));
    EXPECT_FALSE(t.isHidden(4, 3));
    EXPECT_EQ(t.hiddenCount(5), 2u);
    EXPECT_EQ(t.hiddenCount(6), 1u);
    const uint64_t* h = t.hiddenFor(t.cellBox(5).center());
    ASSERT_NE(h, nullptr);
    EXPECT_EQ(h[0], uint64_t(1) << 3);
    EXPECT_EQ(h[1], uint64_t(1) << 6);
}

TEST(PvsTable, BoundToItsImage) {
    auto root = boxes(3);
    Scene s(root);
    s.update();
    const PvsTable t(grid(), s.image(), 0.1, 1.0);
    EXPECT_TRUE(t.matches(s));
    // The same graph in another scene (rebuilt from scratch): still matches.
    Scene again(boxes(3));
    again.update();
    EXPECT_TRUE(t.matches(again)) << t.mismatch(again);
    // Another entry count.
    Scene more(boxes(4));
    more.update();
    EXPECT_NE(t.mismatch(more).find("built for 4 image entries, the scene has 5"), std::string::npos)
        << t.mismatch(more);
    // Same count, one bound moved.
    root->removeChild(size_t(2));
    root->addChild(make<Geometry>(makeBoxMesh(dvec3(2, 5, 0), dvec3(2.5, 6, 1)), make<Material>()));
    s.update();
    EXPECT_NE(t.mismatch(s).find("differ"), std::string::npos) << t.mismatch(s);
}

TEST(PvsTable, BadArgumentsThrow) {
    Scene s(boxes(1));
    s.update();
    PvsTable::Grid g = grid();
    g.cellSize.y = 0;
    EXPECT_THROW(PvsTable(g, s.image(), 0.1, 1.0), std::invalid_argument);
    g = grid();
    g.nx = 1u << 20;
    g.ny = 1u << 10;
    EXPECT_THROW(PvsTable(g, s.image(), 0.1, 1.0), std::invalid_argument);
    EXPECT_THROW(PvsTable(grid(), s.image(), 0.0, 1.0), std::invalid_argument);
    EXPECT_THROW(PvsTable(grid(), s.image(), 2.0, 1.0), std::invalid_argument);
}

TEST(PvsTable, FileRoundTrip) {
    Scene s(boxes(70));
    s.update();
    PvsTable t(grid(), s.image(), 0.25, 0.5);
    t.setHidden(0, 1);
    t.setHidden(79, 70);
    t.setHidden(40, 33);
    const std::string path = ::testing::TempDir() + "pvs_roundtrip.pvs";
    t.save(path);
    const PvsTable u = PvsTable::load(path);
    EXPECT_EQ(u.cellCount(), t.cellCount());
    EXPECT_EQ(u.entryCount(), t.entryCount());
    EXPECT_EQ(u.imageHash(), t.imageHash());
    EXPECT_EQ(u.grid().origin, t.grid().origin);
    EXPECT_EQ(u.grid().cellSize, t.grid().cellSize);
    EXPECT_EQ(u.minNear(), 0.25);
    EXPECT_EQ(u.maxNear(), 0.5);
    EXPECT_TRUE(u.matches(s));
    for (size_t c = 0; c < t.cellCount(); ++c)
        for (uint32_t e = 0; e < t.entryCount(); ++e) ASSERT_EQ(u.isHidden(c, e), t.isHidden(c, e)) << c << " " << e;
    EXPECT_EQ(u.hiddenCount(40), 1u);
    EXPECT_THROW(t.save("/nonexistent-dir/x.pvs"), std::runtime_error);
}

TEST(PvsTable, CorruptFilesThrowNamingTheFault) {
    Scene s(boxes(70));
    s.update();
    PvsTable t(grid(), s.image(), 0.1, 1.0);
    t.setHidden(3, 3);
    const std::string dir = ::testing::TempDir(), good = dir + "pvs_good.pvs", bad = dir + "pvs_bad.pvs";
    t.save(good);
    const std::string g = bytesOf(good);
    ASSERT_EQ(g.size(), 108u + 80u * 2u * 8u);
    ASSERT_NO_THROW(PvsTable::load(good));

    expectLoadFails(dir + "pvs_missing.pvs", "cannot be opened");
    writeBytes(bad, "");
    expectLoadFails(bad, "truncated");
    writeBytes(bad, g.substr(0, 50));
    expectLoadFails(bad, "truncated");
    writeBytes(bad, g.substr(0, g.size() - 1));
    expectLoadFails(bad, "truncated");
    writeBytes(bad, g + "x");
    expectLoadFails(bad, "trailing bytes");
    std::string b = g;
    b[0] = 'X';
    writeBytes(bad, b);
    expectLoadFails(bad, "bad magic");
    b = g;
    poke<uint32_t>(b, 8, 2);
    writeBytes(bad, b);
    expectLoadFails(bad, "version 2");
    // Counts that would ask for terabytes: refused before anything is allocated.
    for (size_t at : {size_t(24), size_t(28), size_t(32)}) {
        b = g;
        poke<uint32_t>(b, at, 0xffffffffu);
        writeBytes(bad, b);
        expectLoadFails(bad, "absurd cell counts");
    }
    b = g;
    poke<uint32_t>(b, 28, 0);
    writeBytes(bad, b);
    expectLoadFails(bad, "grid");
    b = g;
    poke<uint32_t>(b, 12, 0x7fffffffu + 1u);
    poke<uint64_t>(b, 100, (uint64_t(0x7fffffffu) + 64) / 64);
    writeBytes(bad, b);
    expectLoadFails(bad, "absurd entry count");
    b = g;
    poke<uint64_t>(b, 100, 3);  // words per cell not matching the entries
    writeBytes(bad, b);
    expectLoadFails(bad, "do not match");
    b = g;
    poke<uint32_t>(b, 12, 71 + 64);  // entries and words consistent, the file too short for them
    poke<uint64_t>(b, 100, 3);
    writeBytes(bad, b);
    expectLoadFails(bad, "truncated");
    b = g;
    poke<double>(b, 60, -1.0);  // a negative cell size
    writeBytes(bad, b);
    expectLoadFails(bad, "grid");
    b = g;
    poke<double>(b, 36, std::nan(""));
    writeBytes(bad, b);
    expectLoadFails(bad, "grid");
    b = g;
    poke<double>(b, 84, 5.0);  // min near above max near
    writeBytes(bad, b);
    expectLoadFails(bad, "near range");
    b = g;
    poke<uint64_t>(b, 108 + 8, uint64_t(1) << 63);  // cell 0, entry 127: past the 71 entries
    writeBytes(bad, b);
    expectLoadFails(bad, "past the last entry");
}
