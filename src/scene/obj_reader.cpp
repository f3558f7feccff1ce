#include "scene/obj_reader.h"
#include "core/text_file.h"
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string_view>
#include "core/error.h"

namespace rayes {

namespace {

class ObjParser {
 public:
  ObjParser(const std::string& file) : file_(file) {}

  ObjMesh parse(const std::string& text) {
    size_t pos = 0;
    while (pos <= text.size()) {
      size_t end = text.find('\n', pos);
      if (end == std::string::npos) end = text.size();
      ++line_;
      std::string_view l(text.data() + pos, end - pos);
      if (const size_t hash = l.find('#'); hash != std::string_view::npos) l = l.substr(0, hash);
      tokens_.clear();
      split(l);
      if (!tokens_.empty()) statement();
      pos = end + 1;
    }
    // Absolute face indices may refer to vertices defined later in the file.
    const int nv = int(out_.mesh.positions.size());
    size_t off = 0;
    for (size_t f = 0; f < out_.mesh.faceSizes.size(); ++f) {
      for (int k = 0; k < out_.mesh.faceSizes[f]; ++k) {
        const int v = out_.mesh.faceVertices[off + size_t(k)];
        if (v < 0 || v >= nv)
          throw InputError(file_, "line " + std::to_string(out_.faceLine[f]),
                           "vertex index " + std::to_string(v + 1) + " out of range (the file has " +
                               std::to_string(nv) + " vertices)");
      }
      off += size_t(out_.mesh.faceSizes[f]);
    }
    // Texture coordinate indices likewise, once every vt line is read.
    const int nuv = int(out_.mesh.uvs.size());
    off = 0;
    for (size_t f = 0; f < out_.mesh.faceSizes.size() && !out_.mesh.uvIndices.empty(); ++f) {
      for (int k = 0; k < out_.mesh.faceSizes[f]; ++k) {
        const int t = out_.mesh.uvIndices[off + size_t(k)];
        if (t < 0 || t >= nuv)
          throw InputError(file_, "line " + std::to_string(out_.faceLine[f]),
                           "texture coordinate index " + std::to_string(t + 1) + " out of range (the file has " +
                               std::to_string(nuv) + " vt lines)");
      }
      off += size_t(out_.mesh.faceSizes[f]);
    }
    // Texture coordinates no face uses are no uv set.
    if (out_.mesh.uvIndices.empty()) {
      out_.mesh.uvs.clear();
      out_.uvLine.clear();
    }
    return std::move(out_);
  }

 private:
  [[noreturn]] void fail(const std::string& msg) const {
    throw InputError(file_, "line " + std::to_string(line_), msg);
  }

  void split(std::string_view l) {
    size_t i = 0;
    while (i < l.size()) {
      while (i < l.size() && (l[i] == ' ' || l[i] == '\t' || l[i] == '\r')) ++i;
      size_t j = i;
      while (j < l.size() && !(l[j] == ' ' || l[j] == '\t' || l[j] == '\r')) ++j;
      if (j > i) tokens_.push_back(l.substr(i, j - i));
      i = j;
    }
  }

  float number(std::string_view t) const {
    float v = 0;
    const char* b = t.data();
    if (!t.empty() && t[0] == '+') ++b;
    const auto [p, ec] = std::from_chars(b, t.data() + t.size(), v);
    if (ec == std::errc::result_out_of_range) fail("number '" + std::string(t) + "' is out of range for a float");
    if (ec != std::errc() || p != t.data() + t.size()) fail("malformed number '" + std::string(t) + "'");
    if (!std::isfinite(v)) fail("number '" + std::string(t) + "' is not finite");
    return v;
  }

  long integer(std::string_view t) const {
    long v = 0;
    const char* b = t.data();
    if (!t.empty() && t[0] == '+') ++b;
    const auto [p, ec] = std::from_chars(b, t.data() + t.size(), v);
    if (ec != std::errc() || p != t.data() + t.size()) fail("malformed integer '" + std::string(t) + "'");
    if (v < -(1L << 30) || v > (1L << 30)) fail("integer '" + std::string(t) + "' out of range");
    return v;
  }

  void statement() {
    const std::string_view key = tokens_[0];
    if (key == "v") return vertex();
    if (key == "f") return face();
    if (key == "t") return tag();
    if (key == "vt") return textureCoordinate();
    static const char* kSkipped[] = {"vn", "vp", "g", "o", "s", "usemtl", "mtllib"};
    for (const char* s : kSkipped)
      if (key == s) return;
    fail("unsupported OBJ statement '" + std::string(key) + "' (expected v, vt, f, t, or one of vn vp g o s usemtl mtllib)");
  }

  void vertex() {
    if (tokens_.size() != 4 && tokens_.size() != 5) fail("a vertex needs 3 coordinates (and an optional w)");
    Vec3 p{number(tokens_[1]), number(tokens_[2]), number(tokens_[3])};
    if (tokens_.size() == 5) {
      const float w = number(tokens_[4]);
      if (!(w != 0.0f)) fail("vertex weight w must not be zero");
      p = p * (1.0f / w);
    }
    out_.mesh.positions.push_back(p);
    out_.vertexLine.push_back(line_);
  }

  void face() {
    const int n = int(tokens_.size()) - 1;
    if (n < 3) fail("a face needs at least 3 vertices, this one has " + std::to_string(n));
    int withUv = 0;
    for (int k = 1; k <= n; ++k) {
      std::string_view t = tokens_[size_t(k)];
      const size_t slash = t.find('/');
      const std::string_view idx = t.substr(0, slash);
      std::string_view uv;  // the texture index of v/t and v/t/n; empty for v and v//n
      if (slash != std::string_view::npos) {  // v/t, v//n, v/t/n: the normal is checked for shape only
        const std::string_view rest = t.substr(slash + 1);
        int slashes = 0;
        for (char c : rest) {
          if (c == '/') ++slashes;
          else if (!(c == '-' || c == '+' || (c >= '0' && c <= '9'))) fail("malformed face vertex '" + std::string(t) + "'");
        }
        if (slashes > 1) fail("malformed face vertex '" + std::string(t) + "'");
        uv = rest.substr(0, rest.find('/'));
        if (slashes == 0 && uv.empty()) fail("malformed face vertex '" + std::string(t) + "'");
      }
      if (idx.empty()) fail("malformed face vertex '" + std::string(t) + "'");
      out_.mesh.faceVertices.push_back(resolve(integer(idx), out_.mesh.positions.size(), "vertex"));
      if (!uv.empty()) {
        out_.mesh.uvIndices.push_back(resolve(integer(uv), out_.mesh.uvs.size(), "texture coordinate"));
        ++withUv;
      }
    }
    if (withUv != 0 && withUv != n) fail("some corners of this face have a texture coordinate index (v/vt) and some do not");
    // Either every face has texture coordinates or none: a uv set covers the whole mesh.
    const bool faceHasUv = withUv == n;
    if (out_.mesh.faceSizes.empty()) firstFaceHasUv_ = faceHasUv;
    else if (faceHasUv != firstFaceHasUv_)
      fail(std::string("this face has ") + (faceHasUv ? "" : "no ") + "texture coordinate indices (v/vt) and line " +
           std::to_string(out_.faceLine[0]) + "'s face " + (firstFaceHasUv_ ? "has" : "has none") +
           ": give every face of the mesh texture coordinates, or none");
    out_.mesh.faceSizes.push_back(n);
    out_.faceLine.push_back(line_);
  }

  // A one-based or negative (relative to the `defined` items so far) OBJ index, zero-based.
  int resolve(long i, size_t defined, const char* what) const {
    long v = 0;
    if (i > 0) v = i - 1;
    else if (i < 0) v = long(defined) + i;
    else fail(std::string(what) + " index 0 is not valid (OBJ indices start at 1)");
    if (v < 0) fail("relative " + std::string(what) + " index " + std::to_string(i) + " reaches before the first one");
    return int(v);
  }

  void textureCoordinate() {
    if (tokens_.size() < 2 || tokens_.size() > 4) fail("a texture coordinate needs u, and optionally v and w");
    const float u = number(tokens_[1]), v = tokens_.size() > 2 ? number(tokens_[2]) : 0.0f;
    if (tokens_.size() > 3) number(tokens_[3]);  // w: checked, unused
    out_.mesh.uvs.push_back({u, v});
    out_.uvLine.push_back(line_);
  }

  void tag() {
    if (tokens_.size() < 3) fail("a tag needs a name and a count header such as 2/1/0");
    const std::string name(tokens_[1]);
    const std::string_view header = tokens_[2];
    const size_t s1 = header.find('/');
    const size_t s2 = s1 == std::string_view::npos ? s1 : header.find('/', s1 + 1);
    if (s2 == std::string_view::npos) fail("malformed tag header '" + std::string(header) + "' (expected nint/nfloat/nstring)");
    const long ni = integer(header.substr(0, s1)), nf = integer(header.substr(s1 + 1, s2 - s1 - 1)),
               ns = integer(header.substr(s2 + 1));
    if (ni < 0 || nf < 0 || ns < 0) fail("negative count in tag header '" + std::string(header) + "'");
    if (long(tokens_.size()) - 3 != ni + nf + ns)
      fail("tag '" + name + "' declares " + std::to_string(ni + nf + ns) + " arguments but has " +
           std::to_string(tokens_.size() - 3));
    std::vector<int> ints;
    std::vector<float> floats;
    for (long k = 0; k < ni; ++k) ints.push_back(int(integer(tokens_[size_t(3 + k)])));
    for (long k = 0; k < nf; ++k) floats.push_back(number(tokens_[size_t(3 + ni + k)]));
    SubdivMeshDesc& m = out_.mesh;
    if (name == "crease") {
      if (ni < 2 || ni % 2) fail("a crease tag needs pairs of vertex indices");
      if (nf != 1 && nf != ni / 2) fail("a crease tag needs one sharpness, or one per vertex pair");
      for (long k = 0; k < ni / 2; ++k) {
        m.creases.push_back({ints[size_t(2 * k)], ints[size_t(2 * k + 1)], floats[nf == 1 ? 0 : size_t(k)]});
        out_.creaseLine.push_back(line_);
      }
    } else if (name == "corner") {
      if (ni < 1) fail("a corner tag needs vertex indices");
      if (nf != 1 && nf != ni) fail("a corner tag needs one sharpness, or one per vertex");
      for (long k = 0; k < ni; ++k) {
        m.corners.push_back({ints[size_t(k)], floats[nf == 1 ? 0 : size_t(k)]});
        out_.cornerLine.push_back(line_);
      }
    } else if (name == "hole") {
      if (ni < 1 || nf != 0) fail("a hole tag needs face indices and nothing else");
      for (int f : ints) {
        m.holes.push_back(f);
        out_.holeLine.push_back(line_);
      }
    } else if (name == "interpolateboundary") {
      if (ni != 1 || nf != 0 || ints[0] < 0 || ints[0] > 2)
        fail("interpolateboundary takes one integer: 0 none, 1 edges only, 2 edges and corners");
      m.boundary = ints[0] == 0 ? SubdivBoundary::None : ints[0] == 1 ? SubdivBoundary::EdgeOnly : SubdivBoundary::EdgeAndCorner;
    } else {
      fail("unsupported tag '" + name + "' (expected crease, corner, hole or interpolateboundary)");
    }
  }

  std::string file_;
  int line_ = 0;
  bool firstFaceHasUv_ = false;
  std::vector<std::string_view> tokens_;
  ObjMesh out_;
};

}  // namespace

ObjMesh parseObj(const std::string& text, const std::string& file) { return ObjParser(file).parse(text); }

ObjMesh loadObj(const std::string& path) { return parseObj(readTextFile(path, "OBJ file"), path); }

int objLineOf(const ObjMesh& obj, const SubdivInputError& e) {
  using Item = SubdivInputError::Item;
  auto at = [&](const std::vector<int>& lines) {
    return e.index >= 0 && e.index < int(lines.size()) ? lines[size_t(e.index)] : 0;
  };
  switch (e.item) {
    case Item::Vertex: return at(obj.vertexLine);
    case Item::Face: return at(obj.faceLine);
    case Item::Crease: return at(obj.creaseLine);
    case Item::Corner: return at(obj.cornerLine);
    case Item::Hole: return at(obj.holeLine);
    case Item::Uv: return at(obj.uvLine);
    case Item::UvFace: return at(obj.faceLine);
    default: return 0;
  }
}

}  // namespace rayes
