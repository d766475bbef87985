// SHA-256 (FIPS 180-4) through OpenSSL's libcrypto EVP digest interface: a well-kept implementation
// rather than our own.
#include "lodforge/io/file_hash.h"

#include "lodforge/error.h"

#include <openssl/evp.h>

#include <array>
#include <fstream>
#include <memory>

namespace lodforge {
namespace {

using DigestContext = std::unique_ptr<EVP_MD_CTX, void (*)(EVP_MD_CTX*)>;

DigestContext start_digest(const std::string& source) {
    DigestContext ctx(EVP_MD_CTX_new(), EVP_MD_CTX_free);
    if (!ctx || EVP_DigestInit_ex(ctx.get(), EVP_sha256(), nullptr) != 1)
        throw_error(Error::Kind::io, source, "cannot start a SHA-256 digest (OpenSSL)");
    return ctx;
}

std::string finish_digest(EVP_MD_CTX* ctx, const std::string& source) {
    std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
    unsigned int length = 0;
    if (EVP_DigestFinal_ex(ctx, digest.data(), &length) != 1)
        throw_error(Error::Kind::io, source, "SHA-256 digest failed (OpenSSL)");
    static const char* hex = "0123456789abcdef";
    std::string out;
    for (unsigned int i = 0; i < length; ++i) {
        out += hex[digest[i] >> 4];
        out += hex[digest[i] & 15];
    }
    return out;
}

}  // namespace

std::string sha256_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw_error(Error::Kind::io, path, "cannot open the file to hash it");
    DigestContext ctx = start_digest(path);
    std::array<char, 1 << 16> buffer{};
    while (in) {
        in.read(buffer.data(), buffer.size());
        const std::streamsize n = in.gcount();
        if (n > 0 && EVP_DigestUpdate(ctx.get(), buffer.data(), static_cast<std::size_t>(n)) != 1)
            throw_error(Error::Kind::io, path, "SHA-256 digest failed (OpenSSL)");
    }
    if (in.bad()) throw_error(Error::Kind::io, path, "read error while hashing");
    return finish_digest(ctx.get(), path);
}

std::string sha256_text(std::string_view text) {
    DigestContext ctx = start_digest("<text>");
    if (EVP_DigestUpdate(ctx.get(), text.data(), text.size()) != 1)
        throw_error(Error::Kind::io, "<text>", "SHA-256 digest failed (OpenSSL)");
    return finish_digest(ctx.get(), "<text>");
}

}  // namespace lodforge
