#include <memory>
#include <optional>
#include "core/error.h"
#include "geometry/subdiv_mesh.h"
#include "geometry/subdiv_uv.h"
#include "scene/obj_reader.h"
#include "scene/shape_kinds.h"

namespace rayes {

namespace {

// "uv_interpolation" values, OpenSubdiv's FVarLinearInterpolation options in order.
const std::pair<const char*, SubdivUvInterpolation> kUvInterpolations[] = {
    {"none", SubdivUvInterpolation::None},
    {"corners-only", SubdivUvInterpolation::CornersOnly},
    {"corners-plus1", SubdivUvInterpolation::CornersPlus1},
    {"corners-plus2", SubdivUvInterpolation::CornersPlus2},
    {"boundaries", SubdivUvInterpolation::Boundaries},
    {"all", SubdivUvInterpolation::All},
};

// Inline form: "vertices": [[x,y,z], ...], "faces": [[i, j, k, ...], ...] (zero-based),
// optional "creases": [[v0, v1, sharpness], ...], "corners": [[v, sharpness], ...],
// "holes": [f, ...], "uvs": [[s, t], ...] with "uv_faces": [[a, b, c, ...], ...] (indices into
// uvs, one per face vertex), or without uv_faces one uv per vertex.
// The vertices also go to `exact` in double, to be placed before they are rounded (RenderFrame).
SubdivMeshDesc readInlineMesh(const JsonReader& r, const json& shape, const std::string& p, std::vector<Vec3d>& exact) {
  SubdivMeshDesc d;
  const json& vs = r.member(shape, p, "vertices");
  if (!vs.is_array() || vs.empty()) r.fail(p + "/vertices", "expected a non-empty array of points");
  for (size_t k = 0; k < vs.size(); ++k) {
    exact.push_back(r.vec3d(vs[k], p + "/vertices/" + std::to_string(k)));
    d.positions.push_back(exact.back().toFloat());
  }
  const json& fs = r.member(shape, p, "faces");
  if (!fs.is_array() || fs.empty()) r.fail(p + "/faces", "expected a non-empty array of faces");
  for (size_t k = 0; k < fs.size(); ++k) {
    const std::string fp = p + "/faces/" + std::to_string(k);
    if (!fs[k].is_array()) r.fail(fp, "expected an array of vertex indices");
    for (size_t i = 0; i < fs[k].size(); ++i) d.faceVertices.push_back(r.integer(fs[k][i], fp + "/" + std::to_string(i)));
    d.faceSizes.push_back(int(fs[k].size()));
  }
  if (shape.contains("creases")) {
    const json& cs = shape["creases"];
    if (!cs.is_array()) r.fail(p + "/creases", "expected an array of [v0, v1, sharpness]");
    for (size_t k = 0; k < cs.size(); ++k) {
      const std::string cp = p + "/creases/" + std::to_string(k);
      if (!cs[k].is_array() || cs[k].size() != 3) r.fail(cp, "expected [v0, v1, sharpness]");
      d.creases.push_back({r.integer(cs[k][0], cp + "/0"), r.integer(cs[k][1], cp + "/1"), float(r.number(cs[k][2], cp + "/2"))});
    }
  }
  if (shape.contains("corners")) {
    const json& cs = shape["corners"];
    if (!cs.is_array()) r.fail(p + "/corners", "expected an array of [v, sharpness]");
    for (size_t k = 0; k < cs.size(); ++k) {
      const std::string cp = p + "/corners/" + std::to_string(k);
      if (!cs[k].is_array() || cs[k].size() != 2) r.fail(cp, "expected [v, sharpness]");
      d.corners.push_back({r.integer(cs[k][0], cp + "/0"), float(r.number(cs[k][1], cp + "/1"))});
    }
  }
  if (shape.contains("holes")) {
    const json& hs = shape["holes"];
    if (!hs.is_array()) r.fail(p + "/holes", "expected an array of face indices");
    for (size_t k = 0; k < hs.size(); ++k) d.holes.push_back(r.integer(hs[k], p + "/holes/" + std::to_string(k)));
  }
  if (shape.contains("uv_faces") && !shape.contains("uvs")) r.fail(p + "/uv_faces", "'uv_faces' needs 'uvs'");
  if (shape.contains("uvs")) {
    const json& us = shape["uvs"];
    if (!us.is_array() || us.empty()) r.fail(p + "/uvs", "expected a non-empty array of [s, t]");
    for (size_t k = 0; k < us.size(); ++k) {
      const std::string up = p + "/uvs/" + std::to_string(k);
      if (!us[k].is_array() || us[k].size() != 2) r.fail(up, "expected [s, t]");
      d.uvs.push_back({float(r.number(us[k][0], up + "/0")), float(r.number(us[k][1], up + "/1"))});
    }
    if (shape.contains("uv_faces")) {
      const json& ufs = shape["uv_faces"];
      if (!ufs.is_array() || ufs.size() != fs.size())
        r.fail(p + "/uv_faces", "expected one array of uv indices per face (" + std::to_string(fs.size()) + " faces)");
      for (size_t k = 0; k < ufs.size(); ++k) {
        const std::string fp = p + "/uv_faces/" + std::to_string(k);
        if (!ufs[k].is_array() || ufs[k].size() != fs[k].size())
          r.fail(fp, "expected " + std::to_string(fs[k].size()) + " uv indices, one per vertex of face " + std::to_string(k));
        for (size_t i = 0; i < ufs[k].size(); ++i) d.uvIndices.push_back(r.integer(ufs[k][i], fp + "/" + std::to_string(i)));
      }
    } else {
      if (us.size() != vs.size())
        r.fail(p + "/uvs", "without 'uv_faces', one uv per vertex: " + std::to_string(vs.size()) + " vertices, " +
                               std::to_string(us.size()) + " uvs");
      d.uvIndices = d.faceVertices;
    }
  }
  return d;
}

std::string inlinePointer(const std::string& p, const SubdivInputError& e) {
  using Item = SubdivInputError::Item;
  const std::string i = "/" + std::to_string(e.index);
  switch (e.item) {
    case Item::Vertex: return p + "/vertices" + i;
    case Item::Face: return p + "/faces" + i;
    case Item::Crease: return p + "/creases" + i;
    case Item::Corner: return p + "/corners" + i;
    case Item::Hole: return p + "/holes" + i;
    case Item::Uv: return p + "/uvs" + i;
    case Item::UvFace: return p + "/uv_faces" + i;
    default: return p;
  }
}

}  // namespace

// {"type": "subdiv", "file": "x.obj", "scheme": "catmull-clark" | "loop" | "bilinear",
//  "boundary": "edge-and-corner" | "edge-only" | "none", "uv_interpolation": one of
//  kUvInterpolations}, or the inline form above instead of "file". The topology is built (and
// checked) here, once; each transform builds a mesh of transformed control points over it
// (subdivision is affine invariant). The uv set (OBJ vt, inline uvs) does not move with the
// transform: one SubdivUvSet serves every transform and time sample.
ShapeSource readSubdivShape(const ShapeContext& ctx) {
  const JsonReader& r = ctx.reader;
  const json& shape = ctx.shape;
  const std::string& p = ctx.ptr;
  if (shape.contains("file") == shape.contains("faces"))
    r.fail(p, "a subdiv shape needs exactly one of 'file' and 'vertices'/'faces'");
  SubdivScheme scheme = SubdivScheme::CatmullClark;
  if (shape.contains("scheme")) {
    const std::string s = r.string(shape["scheme"], p + "/scheme");
    if (s == "loop") scheme = SubdivScheme::Loop;
    else if (s == "bilinear") scheme = SubdivScheme::Bilinear;
    else if (s != "catmull-clark")
      r.fail(p + "/scheme", "unknown scheme '" + s + "' (expected catmull-clark, loop or bilinear)");
  }
  SubdivUvInterpolation uvInterpolation = SubdivUvInterpolation::All;
  if (shape.contains("uv_interpolation")) {
    const std::string u = r.string(shape["uv_interpolation"], p + "/uv_interpolation");
    std::string known;
    bool found = false;
    for (const auto& [name, value] : kUvInterpolations) {
      known += (known.empty() ? "" : ", ") + std::string(name);
      if (u == name) uvInterpolation = value, found = true;
    }
    if (!found) r.fail(p + "/uv_interpolation", "unknown uv interpolation '" + u + "' (expected " + known + ")");
  }
  std::optional<SubdivBoundary> boundary;  // overrides an OBJ interpolateboundary tag
  if (shape.contains("boundary")) {
    const std::string b = r.string(shape["boundary"], p + "/boundary");
    if (b == "none") boundary = SubdivBoundary::None;
    else if (b == "edge-only") boundary = SubdivBoundary::EdgeOnly;
    else if (b == "edge-and-corner") boundary = SubdivBoundary::EdgeAndCorner;
    else r.fail(p + "/boundary", "unknown boundary rule '" + b + "' (expected edge-and-corner, edge-only or none)");
  }
  std::shared_ptr<const SubdivTopology> topo;
  SubdivMeshDesc desc;
  std::vector<Vec3d> exact;  // inline vertices in double (OBJ vertices are floats as read)
  if (shape.contains("file")) {
    for (const char* k : {"vertices", "creases", "corners", "holes", "uvs", "uv_faces"})
      if (shape.contains(k)) r.fail(p + "/" + k, std::string("'") + k + "' belongs to the inline form, not to 'file'");
    const std::string path = ctx.file("file").string();
    ObjMesh obj = loadObj(path);
    obj.mesh.scheme = scheme;
    obj.mesh.uvInterpolation = uvInterpolation;
    if (boundary) obj.mesh.boundary = *boundary;
    try {
      topo = buildSubdivTopology(obj.mesh);
    } catch (const SubdivInputError& e) {
      const int line = objLineOf(obj, e);
      throw InputError(path, line > 0 ? "line " + std::to_string(line) : "", e.what());
    }
    desc = std::move(obj.mesh);
  } else {
    desc = readInlineMesh(r, shape, p, exact);
    desc.scheme = scheme;
    desc.uvInterpolation = uvInterpolation;
    if (boundary) desc.boundary = *boundary;
    try {
      topo = buildSubdivTopology(desc);
    } catch (const SubdivInputError& e) {
      r.fail(inlinePointer(p, e), e.what());
    }
  }
  auto positions = std::make_shared<const std::vector<Vec3>>(std::move(desc.positions));
  auto exactPositions = exact.empty() ? nullptr : std::make_shared<const std::vector<Vec3d>>(std::move(exact));
  std::shared_ptr<ShapeUvs> uvs;
  if (hasUvSet(*topo)) {
    uvs = std::make_shared<ShapeUvs>();
    uvs->subdiv = std::make_shared<const SubdivUvSet>(topo);
  }
  return {{"file", "scheme", "boundary", "uv_interpolation", "vertices", "faces", "creases", "corners", "holes", "uvs",
           "uv_faces"},
          [topo, positions, exactPositions](const TransformD& xf) {
            std::vector<Vec3> pts(positions->size());
            for (size_t k = 0; k < pts.size(); ++k)
              pts[k] = exactPositions ? xf.roundedPoint((*exactPositions)[k]) : xf.point((*positions)[k]);
            return SubdivMesh::build(topo, std::move(pts))->patches();
          },
          uvs};
}

}  // namespace rayes
