// Checks on a glTF's JSON that must happen before tinygltf sees it, because tinygltf either crashes on
// the input or silently drops what is wrong with it.
#pragma once

#include <cstddef>
#include <string>

namespace lodforge {

// Deepest array/object nesting accepted. Real glTF files stay below 20 levels (extras included);
// tinygltf converts `extras` and `extensions` recursively, so a file nested tens of thousands deep
// overflowed the stack.
inline constexpr int kGltfMaxJsonDepth = 256;

// Throws Error(format) naming `path` when `json` (the .gltf text or a GLB's JSON chunk) is not JSON,
// nests deeper than kGltfMaxJsonDepth, or holds an offset, length, stride or count that is negative or
// not an integer (tinygltf reads those as 0: a negative byteOffset read the start of the buffer).
// Walks the text once without recursion and keeps no document.
void check_gltf_json(const std::string& path, const char* json, std::size_t size);

}  // namespace lodforge
