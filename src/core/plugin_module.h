// Libraries loaded only when a scene needs them. OpenImageIO and OpenVDB, linked into the program,
// cost every render their start-up (Debian's OpenImageIO initialises GDAL, DCMTK, FFmpeg, ... as
// it is loaded: about 95 MiB of resident pages and 0.5 s; OpenVDB about 30 MiB), whether or not
// the scene has an image or a volume. So each is wrapped in a module of ours (a shared object
// beside the program: texture/oiio/ -> librayes_oiio.so, scene/openvdb/ -> librayes_openvdb.so),
// loaded at its first use, with one C entry point; the program sees only interfaces of its own
// (texture/texture_cache.h, scene/vdb_grid.h). bench/history/2026-11.md, "Libraries loaded for
// the scenes that need them", has the figures.
//
// Where a module is looked for: in the folder RAYES_MODULE_DIR names when it is set (tests use
// it to stand for a program copied without its modules), else beside the running program
// (/proc/self/exe): the build puts the modules and every program -- rayes, tests, benchmarks,
// fuzzers -- in its bin/ folder. A module is loaded once per process (thread-safe) and never
// unloaded. Exceptions never cross the entry points: a module reports failures as text.
#pragma once
#include <string>

namespace rayes {

// The address of `symbol` in module `file` (e.g. "librayes_oiio.so"), loading the module at the
// first call for that file. Throws InputError naming the module and the place tried, with
// `what` (what the module is for), when it cannot be loaded.
void* moduleSymbol(const char* file, const char* symbol, const std::string& what);

}  // namespace rayes
