#include "app/film_file.h"
#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <unistd.h>
#include <zlib.h>
#include "core/error.h"

namespace rayes {
namespace {

static_assert(std::endian::native == std::endian::little, "the .film format is little-endian");
constexpr char kMagic[8] = {'R', 'A', 'Y', 'E', 'S', 'F', 'L', 'M'};
constexpr uint32_t kMaxHeaderBytes = 64u << 20;

// Bytes of the sums per pixel of the window, and after them (splat paths, saturations).
constexpr uint64_t kBytesPerPixel = (3 + 1 + 1 + 3 + 1 + 3) * sizeof(double) + sizeof(int32_t) + 2 * sizeof(uint32_t) +
                                    3 * sizeof(__int128);
constexpr uint64_t kTrailerBytes = 2 * sizeof(uint64_t);

nlohmann::json windowJson(const PixelWindow& w) { return nlohmann::json::array({w.x0, w.y0, w.x1, w.y1}); }
PixelWindow windowOf(const nlohmann::json& j) {
  if (!j.is_array() || j.size() != 4) throw std::runtime_error("a window is [x0, y0, x1, y1]");
  return {j[0].get<int>(), j[1].get<int>(), j[2].get<int>(), j[3].get<int>()};
}

nlohmann::json headerJson(const FilmFileHeader& h) {
  return {{"kind", h.kind},
          {"program_version", h.programVersion},
          {"fingerprint", h.fingerprint},
          {"settings", h.settings},
          {"scene", h.scene},
          {"width", h.width},
          {"height", h.height},
          {"crop", windowJson(h.crop)},
          {"window", windowJson(h.window)},
          {"part", h.part},
          {"parts", h.parts},
          {"method", h.method},
          {"light_path_ids", h.lightPathIds},
          {"position",
           {{"pass", h.pass}, {"next", h.next}, {"block_pixels", h.blockPixels}, {"first_hits_end", h.firstHitsEnd}}},
          {"complete", h.complete},
          {"stats", h.stats}};
}

FilmFileHeader headerOf(const nlohmann::json& j) {
  FilmFileHeader h;
  h.kind = j.at("kind").get<std::string>();
  h.programVersion = j.at("program_version").get<std::string>();
  h.fingerprint = j.at("fingerprint").get<std::string>();
  h.settings = j.at("settings");
  h.scene = j.at("scene").get<std::string>();
  h.width = j.at("width").get<int>();
  h.height = j.at("height").get<int>();
  h.crop = windowOf(j.at("crop"));
  h.window = windowOf(j.at("window"));
  h.part = j.at("part").get<int>();
  h.parts = j.at("parts").get<int>();
  h.method = j.at("method").get<std::string>();
  h.lightPathIds = j.at("light_path_ids").get<bool>();
  const auto& p = j.at("position");
  h.pass = p.at("pass").get<int>();
  h.next = p.at("next").get<uint64_t>();
  h.blockPixels = p.at("block_pixels").get<uint64_t>();
  h.firstHitsEnd = p.contains("first_hits_end") ? p.at("first_hits_end").get<uint64_t>() : h.next;
  h.complete = j.at("complete").get<bool>();
  h.stats = j.at("stats");
  return h;
}

struct Closer {
  void operator()(FILE* f) const { std::fclose(f); }
};

// Writes through one FILE, keeping the running crc32; the first failure's errno is kept.
class Writer {
 public:
  explicit Writer(FILE* f) : f_(f) {}
  void bytes(const void* p, size_t n) {
    if (n == 0) return;
    if (!error_ && std::fwrite(p, 1, n, f_) != n) error_ = errno ? errno : EIO;
    // zlib's crc32 takes at most 4 GiB per call.
    for (size_t done = 0; done < n;) {
      const uInt chunk = uInt(std::min<size_t>(n - done, size_t(1) << 30));
      crc_ = crc32(crc_, static_cast<const Bytef*>(p) + done, chunk);
      done += chunk;
    }
  }
  template <class T> void value(const T& v) { bytes(&v, sizeof v); }
  template <class T> void array(const std::vector<T>& v) { bytes(v.data(), v.size() * sizeof(T)); }
  uLong crc() const { return crc_; }
  int error() const { return error_; }

 private:
  FILE* f_;
  uLong crc_ = crc32(0L, Z_NULL, 0);
  int error_ = 0;
};

class Reader {
 public:
  Reader(FILE* f, const std::string& path) : f_(f), path_(path) {}
  void bytes(void* p, size_t n) {
    if (n == 0) return;
    if (std::fread(p, 1, n, f_) != n) throw InputError(path_, "", "cannot read the film file: " + reason());
    for (size_t done = 0; done < n;) {
      const uInt chunk = uInt(std::min<size_t>(n - done, size_t(1) << 30));
      crc_ = crc32(crc_, static_cast<const Bytef*>(p) + done, chunk);
      done += chunk;
    }
  }
  template <class T> void value(T& v) { bytes(&v, sizeof v); }
  template <class T> void array(std::vector<T>& v) { bytes(v.data(), v.size() * sizeof(T)); }
  uLong crc() const { return crc_; }

 private:
  std::string reason() const { return std::ferror(f_) ? std::strerror(errno) : "it ends early"; }
  FILE* f_;
  const std::string& path_;
  uLong crc_ = crc32(0L, Z_NULL, 0);
};

template <class Stream, class Sums>
void sums(Stream& s, Sums& f) {
  s.array(f.rgb); s.array(f.alpha); s.array(f.depth); s.array(f.normal); s.array(f.lod); s.array(f.albedo);
  s.array(f.material); s.array(f.count); s.array(f.hits); s.array(f.splat);
}

}  // namespace

void writeFilmFile(const std::string& path, const FilmFileHeader& header, const Film& film, bool sync) {
  std::unique_ptr<FILE, Closer> f(std::fopen(path.c_str(), "wb"));
  if (!f) throw FilmWriteError(errno, std::strerror(errno));
  Writer w(f.get());
  const std::string text = headerJson(header).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  w.bytes(kMagic, sizeof kMagic);
  w.value(kFilmFormatVersion);
  w.value(uint32_t(text.size()));
  w.bytes(text.data(), text.size());
  sums(w, film.sums());
  w.value(film.sums().splatPaths);
  w.value(film.sums().splatSaturations);
  const uint32_t crc = uint32_t(w.crc());
  w.value(crc);
  int err = w.error();
  if (!err && std::fflush(f.get()) != 0) err = errno;
  if (!err && sync && ::fsync(::fileno(f.get())) != 0) err = errno;
  if (std::fclose(f.release()) != 0 && !err) err = errno;
  if (err) throw FilmWriteError(err, std::strerror(err));
}

namespace {
// Opens the file, reads its header and checks it (readFilmFile, readFilmFileHeader): `f` and `r`
// are left after the header, `size` and `length` are the file's and the header's.
FilmFileHeader readHeaderOf(const std::string& path, std::unique_ptr<FILE, Closer>& f, std::unique_ptr<Reader>& r,
                            uint64_t& size, uint32_t& length) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path, "", "no such film file");
  if (!fs::is_regular_file(path, ec)) throw InputError(path, "", "not a regular file");
  size = fs::file_size(path, ec);
  f.reset(std::fopen(path.c_str(), "rb"));
  if (!f) throw InputError(path, "", std::string("cannot read the film file: ") + std::strerror(errno));
  r = std::make_unique<Reader>(f.get(), path);
  char magic[8] = {};
  if (size < sizeof magic + 8) throw InputError(path, "", "not a .film file (too short)");
  r->bytes(magic, sizeof magic);
  if (std::memcmp(magic, kMagic, sizeof magic) != 0) throw InputError(path, "", "not a .film file");
  uint32_t version = 0;
  length = 0;
  r->value(version);
  if (version != kFilmFormatVersion)
    throw InputError(path, "", "film file format version " + std::to_string(version) + "; this rayes reads version " +
                                   std::to_string(kFilmFormatVersion));
  r->value(length);
  if (length > kMaxHeaderBytes || 16 + uint64_t(length) > size)
    throw InputError(path, "", "truncated or corrupt film file (its header does not fit the file)");
  std::string text(length, '\0');
  r->bytes(text.data(), text.size());
  FilmFileHeader h;
  try {
    h = headerOf(nlohmann::json::parse(text));
  } catch (const std::exception& e) {
    throw InputError(path, "", std::string("corrupt film file header: ") + e.what());
  }
  const PixelWindow& w = h.window;
  if (h.width <= 0 || h.height <= 0 || w.x0 < 0 || w.y0 < 0 || w.x1 > h.width || w.y1 > h.height || w.x1 < w.x0 ||
      w.y1 < w.y0 || h.part < 1 || h.part > h.parts)
    throw InputError(path, "", "corrupt film file header: the window or the part is not in the image");
  return h;
}
}  // namespace

FilmFileHeader readFilmFileHeader(const std::string& path) {
  std::unique_ptr<FILE, Closer> f;
  std::unique_ptr<Reader> r;
  uint64_t size = 0;
  uint32_t length = 0;
  return readHeaderOf(path, f, r, size, length);
}

FilmFile readFilmFile(const std::string& path) {
  std::unique_ptr<FILE, Closer> f;
  std::unique_ptr<Reader> reader;
  uint64_t size = 0;
  uint32_t length = 0;
  const FilmFileHeader h = readHeaderOf(path, f, reader, size, length);
  Reader& r = *reader;
  const PixelWindow& w = h.window;
  const uint64_t expected = 16 + uint64_t(length) + w.pixels() * kBytesPerPixel + kTrailerBytes + sizeof(uint32_t);
  if (size < expected)
    throw InputError(path, "", "truncated film file: " + std::to_string(size) + " of " + std::to_string(expected) + " bytes");
  if (size > expected)
    throw InputError(path, "", "corrupt film file: " + std::to_string(size - expected) + " bytes more than its header describes");
  Film film(h.width, h.height, w);
  Film::Sums& s = film.sums();
  sums(r, s);
  r.value(s.splatPaths);
  r.value(s.splatSaturations);
  const uint32_t computed = uint32_t(r.crc());
  uint32_t stored = 0;
  r.value(stored);
  if (stored != computed) throw InputError(path, "", "corrupt film file: the checksum does not match its content");
  return {std::move(h), std::move(film)};
}

}  // namespace rayes
