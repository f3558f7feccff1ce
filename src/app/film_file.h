// The .film file: a film's accumulated sums with what they are of. One format for the parts of
// a farm split (rayes render --part I/N -o part-I.film, then rayes merge), for checkpoints
// (--checkpoint, --resume) and for a complete render's film (-o x.film). docs/batch-and-farm.md
// describes it for other programs; this is its one reader and writer.
//
//   "RAYESFLM"            8 bytes, the magic
//   format version        uint32 (kFilmFormatVersion)
//   header length L       uint32
//   header                L bytes of JSON (FilmFileHeader: program version, fingerprint, the
//                         settings it covers, full size, crop, window, part, method, position,
//                         the run's stats)
//   sums                  the film's window, pixels in row order, each array whole in this order:
//                         rgb (3 doubles per pixel), alpha, depth, normal (3), lod, albedo (3)
//                         as IEEE doubles; material (int32); count, hits (uint32); splat (3
//                         signed 128-bit fixed-point numbers, Film::kSplatFractionBits);
//                         then splat paths and splat saturations (uint64)
//   checksum              uint32, zlib's crc32 of every byte before it
// Numbers are little-endian. The sums are the film's bits, so a film read back resolves to
// exactly the image it was written from.
//
// Errors: writeFilmFile throws std::runtime_error with the system's reason (errno kept in
// FilmWriteError::error, so a full disk can be told apart); readFilmFile throws InputError naming
// the file: not a film file, another format version, truncated, corrupt (checksum), a header
// that does not describe the sums.
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>
#include <nlohmann/json.hpp>
#include "shading/film.h"

namespace rayes {

inline constexpr uint32_t kFilmFormatVersion = 1;

struct FilmFileHeader {
  std::string kind;            // "part" (of a farm split), "checkpoint", "film" (a complete render)
  std::string programVersion;  // the writer's programVersion() (core/version.h)
  std::string fingerprint;     // of the scene file's bytes and every setting that changes the image
  nlohmann::json settings;     // those settings, readable (a mismatch names the one that differs)
  std::string scene;           // the scene file as named on the command line (messages only)
  int width = 0, height = 0;   // the full image
  PixelWindow crop;            // the frame's pixels: --crop, or the whole image
  PixelWindow window;          // the film's (the crop, or a part's band of it)
  int part = 1, parts = 1;     // --part I/N (1/1: not split)
  std::string method;
  bool lightPathIds = false;   // the parts split light path ids (lt), not rows
  int pass = 0;                // the position of the next batch (Renderer::Position)
  uint64_t next = 0, blockPixels = 0;
  uint64_t firstHitsEnd = 0;   // Renderer::Position::firstHitsEnd (a file without it: `next`)
  bool complete = false;       // every batch of the part (or render) is in the film
  nlohmann::json stats;        // the run's statistics (docs/stats.md), or null
};

struct FilmWriteError : std::runtime_error {
  FilmWriteError(int error, const std::string& what) : std::runtime_error(what), error(error) {}
  int error;  // errno
};

// Writes the file at `path` (straight: callers write a temporary and rename it). With
// `sync`, the data reach the disk (fsync) before it returns.
void writeFilmFile(const std::string& path, const FilmFileHeader& header, const Film& film, bool sync = false);

struct FilmFile {
  FilmFileHeader header;
  Film film;
};
FilmFile readFilmFile(const std::string& path);
// The header alone, checked as readFilmFile checks it; the sums are neither read nor checked
// (`rayes report` of a job's parts reads their stats from it).
FilmFileHeader readFilmFileHeader(const std::string& path);

}  // namespace rayes
