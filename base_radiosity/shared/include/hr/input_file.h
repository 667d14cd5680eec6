// Checked reading of every file a user names (scenes, MGF includes, meshes, MTL libraries, solutions,
// images): regular files only (a directory, FIFO, socket or /dev/zero is refused before a byte is
// read, and opening never blocks), with a size limit from hr/limits.h, so hostile paths can neither
// hang a run nor grow it without bound. Errors are InputError naming the path and what it was for.
#pragma once
#include <cstdint>
#include <string>

namespace hr {

/// The whole file. what says what the file was for ("scene file", "mesh file").
std::string readInputFile(const std::string& path, const char* what, std::uint64_t maxBytes);

/// The same checks without reading, for files a library opens by name (OpenEXR).
void checkInputFile(const std::string& path, const char* what, std::uint64_t maxBytes);

/// Removes a UTF-8 byte-order mark at the start (editors on Windows write one before MGF and OBJ).
void stripUtf8Bom(std::string& text);

}  // namespace hr
