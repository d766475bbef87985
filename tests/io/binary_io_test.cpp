// The one byte reader/writer and tagged section container of the own formats (core/src/io/binary_io.h):
// round trips, and every truncation or corruption is an Error naming the file.
#include "io/binary_io.h"
#include "lodforge/error.h"
#include "lodforge/runtime/lodstrips_runtime.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <functional>

using namespace lodforge;

namespace {

constexpr char kMagic[8] = {'L', 'F', 'T', 'E', 'S', 'T', '\r', '\n'};

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::format) << e.what();
        return e.what();
    }
    ADD_FAILURE() << "no Error thrown";
    return {};
}

std::vector<std::uint8_t> two_sections() {
    binary::Writer a, b;
    a.put(std::uint32_t{7});
    a.put(2.5f);
    a.varint(300);
    a.zigzag(-3);
    a.str("hi");
    b.put_array(std::vector<std::uint16_t>{1, 2, 3});
    return binary::write_container(kMagic, 4, {{"AAAA", &a.bytes}, {"BBBB", &b.bytes}});
}

}  // namespace

TEST(BinaryIo, WriterIsLittleEndianAndVarintsAreLeb128) {
    binary::Writer w;
    w.put(std::uint32_t{0x01020304});
    w.varint(300);   // 0xAC 0x02
    w.zigzag(-1);    // 1
    w.str("ab");
    EXPECT_EQ(w.bytes, (std::vector<std::uint8_t>{4, 3, 2, 1, 0xAC, 0x02, 1, 2, 'a', 'b'}));
}

TEST(BinaryIo, ContainerRoundTripAndSizes) {
    const std::vector<std::uint8_t> file = two_sections();
    EXPECT_EQ(file.size(), binary::container_size({14, 6}));
    EXPECT_EQ(binary::peek_version(file, "t.bin", kMagic, "test"), 4u);
    const auto sec = binary::read_container(file, "t.bin", kMagic, "test", {"AAAA", "BBBB"});
    ASSERT_EQ(sec.size(), 2u);
    binary::Reader a = sec[0].reader("t.bin");
    EXPECT_EQ(a.get<std::uint32_t>("seven"), 7u);
    EXPECT_EQ(a.get<float>("float"), 2.5f);
    EXPECT_EQ(a.left(), 6u);  // varint 300 (2), zigzag (1), string length (1) and bytes (2)
    binary::Reader b = sec[1].reader("t.bin");
    EXPECT_EQ(b.get_array<std::uint16_t>(3, "shorts"), (std::vector<std::uint16_t>{1, 2, 3}));
    b.expect_end("shorts");
    // The engine runtime's parser reads the same container.
    std::uint32_t version = 0;
    std::vector<lodstrips::detail::Section> raw;
    std::string why;
    ASSERT_TRUE(lodstrips::detail::read_container(file.data(), file.size(), kMagic, "test", version, raw, &why)) << why;
    EXPECT_EQ(version, 4u);
    EXPECT_EQ(raw.size(), 2u);
}

TEST(BinaryIo, ReadingPastTheEndNamesFileWhatAndByte) {
    const std::vector<std::uint8_t> file = two_sections();
    const auto sec = binary::read_container(file, "t.bin", kMagic, "test", {"AAAA", "BBBB"});
    binary::Reader b = sec[1].reader("t.bin");
    const std::string msg = error_of([&] { (void)b.get_array<std::uint16_t>(4, "shorts"); });
    EXPECT_NE(msg.find("t.bin"), std::string::npos) << msg;
    EXPECT_NE(msg.find("section BBBB"), std::string::npos) << msg;
    EXPECT_NE(msg.find("shorts"), std::string::npos) << msg;
    EXPECT_NE(msg.find("byte " + std::to_string(sec[1].offset)), std::string::npos) << msg;
    // A count that would overflow the byte count is refused before allocating.
    binary::Reader c = sec[1].reader("t.bin");
    EXPECT_FALSE(error_of([&] { (void)c.get_array<std::uint64_t>(~std::uint64_t(0) / 4, "huge"); }).empty());
    binary::Reader d = sec[0].reader("t.bin");
    (void)d.get<std::uint32_t>("seven");
    EXPECT_NE(error_of([&] { d.expect_end("header"); }).find("10 unexpected bytes after the header"), std::string::npos);
}

TEST(BinaryIo, EveryTruncationAndByteFlipIsRejected) {
    const std::vector<std::uint8_t> file = two_sections();
    for (std::size_t n = 0; n < file.size(); ++n) {
        const std::vector<std::uint8_t> cut(file.begin(), file.begin() + std::ptrdiff_t(n));
        const std::string msg =
            error_of([&] { (void)binary::read_container(cut, "cut.bin", kMagic, "test", {"AAAA", "BBBB"}); });
        EXPECT_NE(msg.find("cut.bin"), std::string::npos) << n << ": " << msg;
    }
    for (std::size_t i = 0; i < file.size(); ++i) {
        std::vector<std::uint8_t> bad = file;
        bad[i] ^= 0x10;
        EXPECT_FALSE(error_of([&] { (void)binary::read_container(bad, "flip.bin", kMagic, "test", {"AAAA", "BBBB"}); })
                         .empty())
            << "byte " << i;
    }
}

TEST(BinaryIo, WrongMagicVersionlessFileAndUnexpectedSections) {
    std::vector<std::uint8_t> file = two_sections();
    EXPECT_NE(error_of([&] { (void)binary::peek_version({'L', 'F'}, "x.bin", kMagic, "test"); }).find("not a test file"),
              std::string::npos);
    EXPECT_NE(error_of([&] { (void)binary::peek_version({kMagic, kMagic + 8}, "x.bin", kMagic, "test"); }).find("truncated"),
              std::string::npos);
    EXPECT_NE(error_of([&] { (void)binary::read_container(file, "x.bin", kMagic, "test", {"AAAA", "CCCC"}); })
                  .find("expected section CCCC"),
              std::string::npos);
    EXPECT_NE(error_of([&] { (void)binary::read_container(file, "x.bin", kMagic, "test", {"AAAA"}); })
                  .find("expected 1 sections"),
              std::string::npos);
}

TEST(BinaryIo, FilesAreWrittenAtomicallyAndReadWhole) {
    lodforge::test::ScratchDir dir("binary-io");
    const std::vector<std::uint8_t> file = two_sections();
    binary::write_file(dir.file("a.bin"), file);
    EXPECT_EQ(binary::read_file(dir.file("a.bin"), "a test file"), file);
    try {
        (void)binary::read_file(dir.path().string(), "a test file");
        ADD_FAILURE() << "a directory was read";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::io);
    }
}

TEST(BinaryIo, ChecksumIsCrc32) {
    const std::string text = "123456789";
    EXPECT_EQ(binary::checksum(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), 0xCBF43926u);
}
