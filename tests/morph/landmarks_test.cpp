// Landmark files: round trip, and every kind of damage gives an error naming the file and the entry.
#include "lodforge/error.h"
#include "lodforge/morph/landmarks.h"

#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <fstream>

namespace {

using namespace lodforge;

std::string write_text(const lodforge::test::ScratchDir& dir, const std::string& name, const std::string& text)
{
    const std::string path = (dir.path() / name).string();
    std::ofstream(path) << text;
    return path;
}

Error::Kind kind_of_read(const std::string& path, std::string* message = nullptr)
{
    try {
        read_landmarks(path);
    } catch (const Error& e) {
        if (message) *message = e.what();
        return e.kind();
    }
    ADD_FAILURE() << "no error for " << path;
    return Error::Kind::argument;
}

TEST(Landmarks, RoundTrip)
{
    lodforge::test::ScratchDir dir("landmarks");
    Landmarks in;
    in.pairs = {{0, 7}, {12, 3}, {4000000000u, 1}};
    const std::string path = (dir.path() / "l.json").string();
    write_landmarks(in, path);
    const Landmarks out = read_landmarks(path);
    EXPECT_EQ(out.pairs, in.pairs);
}

TEST(Landmarks, BadFilesNameTheProblem)
{
    lodforge::test::ScratchDir dir("landmarks");
    std::string message;
    EXPECT_EQ(kind_of_read((dir.path() / "missing.json").string(), &message), Error::Kind::io);
    EXPECT_NE(message.find("missing.json"), std::string::npos);
    EXPECT_EQ(kind_of_read(write_text(dir, "a.json", "{\"format\": \"lodforge-landmarks\", "), &message),
              Error::Kind::format);
    EXPECT_NE(message.find("a.json"), std::string::npos);
    EXPECT_EQ(kind_of_read(write_text(dir, "b.json", "{\"format\": \"other\", \"version\": 1, \"pairs\": []}")),
              Error::Kind::format);
    EXPECT_EQ(kind_of_read(write_text(dir, "c.json", "{\"format\": \"lodforge-landmarks\", \"version\": 2, \"pairs\": []}")),
              Error::Kind::format);
    EXPECT_EQ(kind_of_read(write_text(dir, "d.json",
                                      "{\"format\": \"lodforge-landmarks\", \"version\": 1, \"pairs\": [[1, 2], [3]]}"),
                           &message),
              Error::Kind::format);
    EXPECT_NE(message.find("pair 1"), std::string::npos);
    EXPECT_EQ(kind_of_read(write_text(dir, "e.json",
                                      "{\"format\": \"lodforge-landmarks\", \"version\": 1, \"pairs\": [[1, -2]]}")),
              Error::Kind::format);
    EXPECT_EQ(kind_of_read(write_text(dir, "f.json",
                                      "{\"format\": \"lodforge-landmarks\", \"version\": 1, \"pairs\": [[1.5, 2]]}")),
              Error::Kind::format);
}

// landmarks_fuzz's finding: a member of another type than the format says (`"format": 1`) made nlohmann
// throw its own type_error, which ended the fuzzer (and reached the CLI as a message without the file).
TEST(Landmarks, MembersOfTheWrongTypeAreFormatErrorsNamingTheFile)
{
    lodforge::test::ScratchDir dir("landmarks");
    const char* const texts[] = {
        "{\"format\": 1}",  // the fuzzer's crashing input
        "{\"format\": [\"lodforge-landmarks\"], \"version\": 1, \"pairs\": []}",
        "{\"format\": null, \"version\": 1, \"pairs\": []}",
        "{\"format\": \"lodforge-landmarks\", \"version\": \"1\", \"pairs\": []}",
        "{\"format\": \"lodforge-landmarks\", \"version\": 4294967297, \"pairs\": []}",  // 1 as a 32-bit int
        "{\"format\": \"lodforge-landmarks\", \"version\": 1, \"pairs\": {\"0\": [1, 2]}}",
        "{\"format\": \"lodforge-landmarks\", \"version\": 1, \"pairs\": [[18446744073709551615, 2]]}",
        "[\"format\", \"lodforge-landmarks\"]",
        "\"lodforge-landmarks\"",
    };
    int n = 0;
    for (const char* text : texts) {
        SCOPED_TRACE(text);
        const std::string name = "wrong-type-" + std::to_string(n++) + ".json";
        std::string message;
        EXPECT_EQ(kind_of_read(write_text(dir, name, text), &message), Error::Kind::format);
        EXPECT_NE(message.find(name), std::string::npos) << message;
    }
}

TEST(Landmarks, CheckRejectsOutOfRangeAndRepeats)
{
    Landmarks l;
    l.pairs = {{0, 1}, {5, 2}};
    EXPECT_NO_THROW(check_landmarks(l, 6, 3, "l.json"));
    try {
        check_landmarks(l, 5, 3, "l.json");
        ADD_FAILURE() << "out-of-range vertex of A accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::invalid);
        EXPECT_NE(std::string(e.what()).find("vertex 5 of mesh A"), std::string::npos) << e.what();
    }
    EXPECT_THROW(check_landmarks(l, 6, 2, "l.json"), Error);
    l.pairs.push_back({0, 0});
    EXPECT_THROW(check_landmarks(l, 6, 3, "l.json"), Error);
}

}  // namespace
