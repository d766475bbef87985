// Every reader, through the command that reads it, answers the same damaged files the same way
// (issue 32): exit 1, one line "lodforge: error: FILE: problem" naming the file exactly as the user gave
// it, never "internal error", never a path the user did not give (a temporary, an output), and no
// output file left. The damages: empty, bytes of another kind, the first half of a good file (not for
// OBJ), and for the own binary formats one flipped byte (their checksums must catch it).
#include "io/io_test_util.h"
#include "support/cli_run.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace {
namespace fs = std::filesystem;
using lodforge::test::CliRun;
using lodforge::test::quoted;
using lodforge::test::run_cli;
using lodforge::test::ScratchDir;
using lodforge::test::shared_data;
using lodforge::test::write_text;

std::string bad_files_read(const std::string& path) {
    const std::vector<std::uint8_t> bytes = lodforge::test::read_bytes(path);
    return {bytes.begin(), bytes.end()};
}

// One good file of a format, the commands that read it ("%" stands for the file), and whether one
// flipped byte must be an error (the checksummed own formats).
struct ReaderCase {
    std::string good;
    std::vector<std::string> commands;
    bool checksummed = false;
};

// The checks of the file comment, for one command on one damaged file; returns the message.
std::string expect_clean_failure(const std::string& command, const std::string& file, const ScratchDir& dir) {
    std::string args = command;
    args.replace(args.find('%'), 1, quoted(file));
    const CliRun r = run_cli(args);
    SCOPED_TRACE(args + "\n" + r.out);
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(r.out.rfind("lodforge: error: " + file + ": ", 0), 0u) << "the message must start with the file";
    EXPECT_EQ(r.out.find('\n'), r.out.size() - 1) << "one line";
    EXPECT_EQ(r.out.find("internal error"), std::string::npos);
    EXPECT_EQ(r.out.find("tmp-"), std::string::npos) << "a temporary's name";
    // The scratch directory may appear only as part of the file's own name.
    std::string rest = r.out;
    for (std::size_t at; (at = rest.find(file)) != std::string::npos;) rest.erase(at, file.size());
    EXPECT_EQ(rest.find(dir.path().string()), std::string::npos) << "a path the user did not give";
    EXPECT_FALSE(fs::exists(dir.file("out.ply")));
    EXPECT_FALSE(fs::exists(dir.file("out.lfmorph")));
    return r.out;
}

TEST(CliBadFiles, EveryReaderNamesTheFileAndExitsOneOnDamagedInput) {
    ScratchDir dir("cli-bad-files");
    const auto make = [&](const std::string& args) {
        const CliRun r = run_cli(args);
        ASSERT_EQ(r.exit_code, 0) << args << "\n" << r.out;
    };
    // Small good files of every format, written by the CLI itself (the sizes keep the test quick).
    const std::string ply = dir.file("good.ply");
    make("simplify " + quoted(shared_data("color-open3d-small/color.ply")) + " -o " + quoted(ply) +
         " --triangles 16 --mode cluster");
    make("convert " + quoted(ply) + " " + quoted(dir.file("good.obj")));
    make("convert " + quoted(ply) + " " + quoted(dir.file("good.glb")));
    make("octree build " + quoted(ply) + " -o " + quoted(dir.file("good.lfo")) + " --max-triangles 6");
    make("mcoctree build " + quoted(ply) + " -o " + quoted(dir.file("good.mco")) + " --resolution 4");
    make("strips " + quoted(ply) + " -o " + quoted(dir.file("good.lodstrips")));
    const std::string cube = shared_data("morph-animated-morph-cube/AnimatedMorphCube.gltf");
    make("morph build " + quoted(cube) + " -o " + quoted(dir.file("good.lfmorph")) + " --frames 2 --levels 0.5 --strips " +
         quoted(dir.file("good.lfmstrips")));
    write_text(dir.file("good.gltf"), bad_files_read(cube));  // its .bin is not beside it: fine for damage
    write_text(dir.file("good-preset.json"), R"({"version": 1, "name": "p", "levels": [{"ratio": 0.5}]})");
    write_text(dir.file("good-landmarks.json"),
                    R"({"format": "lodforge-landmarks", "version": 1, "pairs": [[0, 5], [12, 7], [3, 3]]})");
    // The good files themselves pass the commands below (so a failure is the damage's).
    make("simplify " + quoted(ply) + " -o " + quoted(dir.file("ok.ply")) + " --preset " +
         quoted(dir.file("good-preset.json")));

    const std::string out = " -o " + quoted(dir.file("out.ply"));
    const std::string convert = "convert % " + quoted(dir.file("out.ply"));
    const std::vector<ReaderCase> cases = {
        {ply, {"info %", convert}},
        {dir.file("good.obj"), {"info %", convert}},
        {dir.file("good.gltf"), {"info %", convert}},
        {dir.file("good.glb"), {"info %", convert}},
        {dir.file("good.lfo"), {"octree info %", "octree extract % --level 0" + out}},
        {dir.file("good.mco"), {"mcoctree info %", "mcoctree extract % --priority 0" + out}, true},
        {dir.file("good.lodstrips"), {"strips info %", "strips extract % --lod 0.5" + out}, true},
        {dir.file("good.lfmorph"), {"morph info %", "morph extract % --t 0 --lod 1" + out}, true},
        {dir.file("good.lfmstrips"), {"morph info %"}, true},
        {dir.file("good-preset.json"), {"simplify " + quoted(ply) + out + " --preset %"}},
        {dir.file("good-landmarks.json"),
         {"morph build " + quoted(ply) + " " + quoted(ply) + " -o " + quoted(dir.file("out.lfmorph")) + " --landmarks %"}},
    };
    for (const ReaderCase& c : cases) {
        const std::string bytes = bad_files_read(c.good);
        ASSERT_GT(bytes.size(), 16u) << c.good;
        const std::string ext = fs::path(c.good).extension().string();
        std::string garbage;
        for (int i = 0; i < 300; ++i) garbage += static_cast<char>((i * 37 + 11) & 0xff);
        std::vector<std::pair<std::string, std::string>> damaged = {{"empty", ""}, {"garbage", garbage}};
        // The first half of an OBJ is an OBJ with fewer lines (possibly a valid one).
        if (ext != ".obj") damaged.emplace_back("half", bytes.substr(0, bytes.size() / 2));
        if (c.checksummed || ext == ".lfo") {
            std::string flipped = bytes;
            // An .lfo's mesh chunks are checked when loaded (OctreeBuild.EveryFlippedByteIsDetected), so
            // whether a flip a third of the way in is seen depends on the level read; its index, just
            // before the 16-byte footer, is read by every command.
            flipped[ext == ".lfo" ? bytes.size() - 24 : bytes.size() / 3] ^= 0x10;
            damaged.emplace_back("flipped", flipped);
        }
        for (const auto& [kind, content] : damaged) {
            const std::string file = dir.file(kind + "-" + fs::path(c.good).filename().string());
            write_text(file, content);
            for (const std::string& command : c.commands) {
                const std::string message = expect_clean_failure(command, file, dir);
                // `morph info` picks its reader by the magic; a damaged .lfmstrips was called a bad .lfmorph.
                if (ext == ".lfmstrips") {
                    EXPECT_EQ(message.find(".lfmorph"), std::string::npos) << message;
                }
            }
        }
    }
}

}  // namespace
