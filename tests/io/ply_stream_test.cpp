// The streaming reader in caller-sized chunks gives exactly what read_ply gives; the writer fails
// cleanly; progress and cancellation work in both directions.

#include "io/ply_internal.h"
#include "ply_test_util.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <sys/resource.h>

using namespace lodforge;
using namespace lodforge::test;

namespace {

struct Recorder : Progress {
    std::vector<double> fractions;
    int cancel_after = -1;
    void report(double fraction, std::string_view) override { fractions.push_back(fraction); }
    bool cancelled() const override { return cancel_after >= 0 && static_cast<int>(fractions.size()) > cancel_after; }
};

void stream_and_compare(const std::string& path, std::size_t vertex_chunk, std::size_t face_chunk) {
    SCOPED_TRACE(path + " chunks " + std::to_string(vertex_chunk) + "/" + std::to_string(face_chunk));
    const Mesh whole = read_ply(path);
    PlyReader reader(path);
    const PlyVertexAttributes attrs = reader.vertex_attributes();
    std::vector<Vec3f> positions, normals;
    std::vector<Vec4f> colors;
    std::vector<Vec3f> p(vertex_chunk), n(attrs.normals ? vertex_chunk : 0);
    std::vector<Vec4f> c(attrs.colors ? vertex_chunk : 0);
    std::vector<std::uint32_t> indices;
    PlyFaceChunk faces;
    std::uint64_t last_position = reader.position();
    while (const PlyElement* e = reader.current_element()) {
        const std::uint64_t before = reader.remaining();
        if (reader.at_vertices()) {
            EXPECT_EQ(e->name, "vertex");
            const std::size_t got = reader.read_vertices(p, n, c);
            ASSERT_GT(got, 0u);
            positions.insert(positions.end(), p.begin(), p.begin() + static_cast<std::ptrdiff_t>(got));
            normals.insert(normals.end(), n.begin(), n.begin() + static_cast<std::ptrdiff_t>(n.empty() ? 0 : got));
            colors.insert(colors.end(), c.begin(), c.begin() + static_cast<std::ptrdiff_t>(c.empty() ? 0 : got));
            if (reader.current_element() == e) {
                EXPECT_EQ(reader.remaining(), before - got);
            }
        } else if (reader.at_faces()) {
            faces.clear();
            const std::size_t got = reader.read_faces(face_chunk, faces);
            ASSERT_GT(got, 0u);
            EXPECT_EQ(faces.faces_read, got);
            indices.insert(indices.end(), faces.indices.begin(), faces.indices.end());
        } else {
            reader.skip_element();
        }
        EXPECT_GE(reader.position(), last_position);
        last_position = reader.position();
    }
    EXPECT_EQ(positions, whole.positions);
    EXPECT_EQ(normals, whole.normals);
    EXPECT_EQ(colors, whole.colors);
    EXPECT_EQ(indices, whole.indices);
}

}  // namespace

TEST(PlyStream, DragonRes2InChunksMatchesReadPly) {
    const std::string ascii = shared_data("scan-dragon/dragon_vrip_res2.ply");
    stream_and_compare(ascii, 1000, 4096);
    stream_and_compare(ascii, 77777, 1);
    // The same in binary, both byte orders, with chunks that do not divide the counts or the buffer.
    ScratchDir dir("ply-stream");
    const Mesh m = read_ply(ascii);
    for (PlyEncoding enc : {PlyEncoding::binary_little_endian, PlyEncoding::binary_big_endian}) {
        WriteOptions o;
        o.ply_encoding = enc;
        write_ply(m, dir.file("d.ply"), o);
        stream_and_compare(dir.file("d.ply"), 999, 3333);
        EXPECT_EQ(read_ply(dir.file("d.ply")).positions, m.positions);
    }
}

TEST(PlyStream, ColouredBinaryInChunks) {
    stream_and_compare(shared_data("color-open3d-frag115/frag_115.ply"), 4096, 10000);
    stream_and_compare(shared_data("scan-bunny/bun_zipper.ply"), 5000, 7);
}

TEST(PlyStream, ReaderReadsFromMemoryLikeFromAFile) {
    const std::string path = shared_data("scan-lucy100k/Lucy100k.ply");
    const std::string bytes = read_file(path);
    PlyReader reader(bytes_of(bytes), "lucy-in-memory.ply");
    const Mesh a = read_ply(reader);
    const Mesh b = read_ply(path);
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.indices, b.indices);
    EXPECT_EQ(reader.position(), bytes.size());
}

TEST(PlyStream, ProgressIsReportedAndCancelStopsReading) {
    const std::string path = shared_data("scan-dragon/dragon_vrip_res2.ply");
    Recorder r;
    read_ply(path, &r);
    ASSERT_GE(r.fractions.size(), 3u);
    EXPECT_EQ(r.fractions.back(), 1.0);
    for (std::size_t i = 1; i < r.fractions.size(); ++i) EXPECT_GE(r.fractions[i], r.fractions[i - 1]);

    Recorder cancel;
    cancel.cancel_after = 1;
    EXPECT_EQ(catch_error([&] { read_ply(path, &cancel); }).kind, Error::Kind::cancelled);
}

TEST(PlyWriter, CancelLeavesNoFile) {
    ScratchDir dir("ply-cancel");
    const Mesh m = read_ply(shared_data("scan-dragon/dragon_vrip_res2.ply"));
    Recorder cancel;
    cancel.cancel_after = 2;
    const std::string out = dir.file("out.ply");
    WriteOptions o;
    o.ply_encoding = PlyEncoding::ascii;
    EXPECT_EQ(catch_error([&] { write_ply(m, out, o, &cancel); }).kind, Error::Kind::cancelled);
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(PlyWriter, FullDiskIsAnIoErrorAndLeavesNothingBehind) {
    ScratchDir dir("ply-full");
    const Mesh m = read_ply(shared_data("scan-dragon/dragon_vrip_res3.ply"));
    const std::string out = dir.file("out.ply");
    write_file(out, "previous contents");
    // Simulate a full disk: a file size limit makes writes fail with EFBIG (SIGXFSZ ignored).
    std::signal(SIGXFSZ, SIG_IGN);
    rlimit old{};
    ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &old), 0);
    rlimit small = old;
    small.rlim_cur = 64 * 1024;
    ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
    const CaughtError e = catch_error([&] { write_ply(m, out); });
    setrlimit(RLIMIT_FSIZE, &old);
    EXPECT_EQ(e.kind, Error::Kind::io);
    EXPECT_NE(e.message.find(out), std::string::npos) << e.message;
    EXPECT_EQ(read_file(out), "previous contents");  // the target is untouched
    std::size_t files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir.path())) files += entry.is_regular_file();
    EXPECT_EQ(files, 1u);  // the temporary file was removed
}

TEST(PlyWriter, UnwritableTargetAndInconsistentMeshes) {
    ScratchDir dir("ply-badwrite");
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.indices = {0, 1, 2};
    const std::string nowhere = dir.file("no/such/dir/out.ply");
    CaughtError e = catch_error([&] { write_ply(m, nowhere); });
    EXPECT_EQ(e.kind, Error::Kind::io);
    EXPECT_NE(e.message.find(nowhere), std::string::npos);

    Mesh bad = m;
    bad.normals = {{0, 0, 1}};
    EXPECT_EQ(catch_error([&] { write_ply(bad, dir.file("a.ply")); }).kind, Error::Kind::argument);
    bad = m;
    bad.indices = {0, 1, 3};
    EXPECT_EQ(catch_error([&] { write_ply(bad, dir.file("a.ply")); }).kind, Error::Kind::argument);
    EXPECT_FALSE(std::filesystem::exists(dir.file("a.ply")));
}

TEST(PlyWriter, HeaderIsWhatTheDocsSay) {
    ScratchDir dir("ply-header");
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.colors = {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 0.5f}};
    m.indices = {0, 1, 2};
    m.materials.emplace_back().base_color_texture.path = "textures/skin.png";
    WriteOptions o;
    o.ply_encoding = PlyEncoding::ascii;
    write_ply(m, dir.file("h.ply"), o);
    const std::string text = read_file(dir.file("h.ply"));
    EXPECT_EQ(text,
              "ply\nformat ascii 1.0\ncomment written by LodForge\ncomment TextureFile textures/skin.png\n"
              "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
              "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n"
              "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
              "0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 128\n3 0 1 2\n");
}

TEST(PlyStream, TinyReadBuffersGiveTheSameResult) {
    // Every refill, buffer growth and token-across-the-boundary path, on real files.
    const std::vector<std::string> files = {shared_data("color-open3d-small/color.ply"),
                                            shared_data("tex-ply-wedge-uv/laurana500.ply"),
                                            shared_data("scan-dragon/dragon_vrip_res4.ply")};
    std::vector<Mesh> reference;
    for (const std::string& f : files) reference.push_back(read_ply(f));
    for (std::size_t buffer : {1, 7, 64, 1000}) {
        ply_detail::set_file_buffer_size(buffer);
        for (std::size_t i = 0; i < files.size(); ++i) {
            SCOPED_TRACE(files[i] + " buffer " + std::to_string(buffer));
            const Mesh m = read_ply(files[i]);
            EXPECT_EQ(m.positions, reference[i].positions);
            EXPECT_EQ(m.colors, reference[i].colors);
            EXPECT_EQ(m.texcoords, reference[i].texcoords);
            EXPECT_EQ(m.indices, reference[i].indices);
        }
        // Skipping unknown elements with a tiny buffer seeks past it.
        ScratchDir dir("ply-tiny");
        const std::string path = dir.file("skip.ply");
        std::string bytes = "ply\nformat binary_little_endian 1.0\nelement blob 1000\nproperty double a\n"
                            "element vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
        bytes += std::string(8000, '\0');
        const float xyz[3] = {1, 2, 3};
        bytes.append(reinterpret_cast<const char*>(xyz), 12);
        write_file(path, bytes);
        EXPECT_EQ(read_ply(path).positions, (std::vector<Vec3f>{{1, 2, 3}}));
    }
    ply_detail::set_file_buffer_size(std::size_t(1) << 20);
}

// Two readers of one ASCII file can split an element (the octree soup parses on two threads this way):
// the second, moved to a line, reads the records from there and names lines as one reader does.
TEST(PlyStream, AsciiReaderMovedToARecordReadsFromThere) {
    ScratchDir dir("ply-seek");
    const std::string path = dir.file("seek.ply");
    const std::string head = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                             "element face 3\nproperty list uchar int vertex_indices\nend_header\n";
    const std::string body = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n\n3 0 2 3\n3 1 2 x\n";
    std::ofstream(path, std::ios::binary) << head << body;
    const std::uint64_t second_face = head.size() + body.find("\n\n3 0 2 3") + 1;  // the blank line before it
    PlyReader reader(path);
    reader.seek_ascii_record(1, 1, second_face, 14);
    ASSERT_TRUE(reader.at_faces());
    EXPECT_EQ(reader.remaining(), 2u);
    PlyFaceChunk faces;
    EXPECT_EQ(reader.read_faces(1, faces), 1u);
    EXPECT_EQ(faces.indices, (std::vector<std::uint32_t>{0, 2, 3}));
    EXPECT_EQ(reader.line(), 16u);
    try {
        reader.read_faces(1, faces);
        FAIL() << "a bad index was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("line 17"), std::string::npos) << e.what();
    }
    EXPECT_THROW(reader.seek_ascii_record(1, 0, head.size(), 9), Error);  // backwards
    PlyReader binary(shared_data("color-open3d-frag115/frag_115.ply"));
    EXPECT_THROW(binary.seek_ascii_record(0, 0, binary.position(), 0), Error);
}
