// host/physics/mesh.cpp - see mesh.h.
#include "mesh.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <utility>

namespace articula::host {

namespace {

[[noreturn]] void fail(const std::string& name, int line, const std::string& problem) {
  throw MeshError(name + ": " + (line > 0 ? "line " + std::to_string(line) + ": " : "") + problem);
}

// A number token, all of it, finite.
double number(const std::string& token, const std::string& name, int line) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(token.c_str(), &end);
  if (token.empty() || end != token.c_str() + token.size()) fail(name, line, "bad number \"" + token + "\"");
  if (!std::isfinite(v) || errno == ERANGE) fail(name, line, "not a finite number \"" + token + "\"");
  return v;
}

std::vector<std::string> tokens(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream in(line);
  for (std::string t; in >> t;) out.push_back(t);
  return out;
}

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Merges equal vertices (bit for bit), keeps only used ones, drops triangles without area.
TriangleMesh finish(const std::vector<Vec3<double>>& raw, const std::vector<std::array<uint32_t, 3>>& raw_tris,
                    const std::string& name) {
  TriangleMesh m;
  std::map<std::array<double, 3>, uint32_t> index;
  std::vector<uint32_t> remap(raw.size(), UINT32_MAX);
  auto vertex = [&](uint32_t i) {
    if (remap[i] == UINT32_MAX) {
      const Vec3<double>& v = raw[i];
      const std::array<double, 3> key = {v.x + 0.0, v.y + 0.0, v.z + 0.0};  // + 0.0: -0 is 0
      auto it = index.emplace(key, uint32_t(m.vertices.size())).first;
      if (it->second == m.vertices.size()) m.vertices.push_back(v);
      remap[i] = it->second;
    }
    return remap[i];
  };
  for (const auto& t : raw_tris) {
    const std::array<uint32_t, 3> r = {vertex(t[0]), vertex(t[1]), vertex(t[2])};
    const Vec3<double>& a = m.vertices[r[0]];
    const Vec3<double> n = cross(m.vertices[r[1]] - a, m.vertices[r[2]] - a);
    if (n.x == 0 && n.y == 0 && n.z == 0) continue;  // a line or a point
    m.triangles.push_back(r);
  }
  if (m.triangles.empty())
    fail(name, 0, raw_tris.empty() ? "no triangles: nothing to collide with" : "every triangle has zero area: nothing to collide with");
  return m;
}

uint32_t u32_le(const unsigned char* p) { return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24; }

float f32_le(const unsigned char* p) {
  const uint32_t u = u32_le(p);
  float f;
  std::memcpy(&f, &u, sizeof f);
  return f;
}

TriangleMesh parse_binary_stl(const std::string& bytes, const std::string& name) {
  if (bytes.size() < 84)
    fail(name, 0, "truncated binary STL: " + std::to_string(bytes.size()) + " bytes, less than the 84 of its header");
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  const uint64_t n = u32_le(p + 80);
  const uint64_t want = 84 + 50 * n;
  if (bytes.size() < want)
    fail(name, 0, "truncated binary STL: its header says " + std::to_string(n) + " triangles (" + std::to_string(want) +
                      " bytes), the file has " + std::to_string(bytes.size()) + " bytes");
  if (bytes.size() > want)
    fail(name, 0, "not a binary STL: its header says " + std::to_string(n) + " triangles (" + std::to_string(want) +
                      " bytes), the file has " + std::to_string(bytes.size() - want) + " bytes more (and it does not start with \"solid\")");
  std::vector<Vec3<double>> raw;
  std::vector<std::array<uint32_t, 3>> tris;
  raw.reserve(size_t(3 * n));
  tris.reserve(size_t(n));
  for (uint64_t t = 0; t < n; ++t) {
    const unsigned char* q = p + 84 + 50 * t + 12;  // after the normal
    for (int k = 0; k < 3; ++k) {
      const double x = f32_le(q + 12 * k), y = f32_le(q + 12 * k + 4), z = f32_le(q + 12 * k + 8);
      if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
        fail(name, 0, "triangle " + std::to_string(t + 1) + ": a vertex is not a finite number");
      raw.push_back(make_vec3(x, y, z));
    }
    tris.push_back({uint32_t(3 * t), uint32_t(3 * t + 1), uint32_t(3 * t + 2)});
  }
  return finish(raw, tris, name);
}

TriangleMesh parse_ascii_stl(const std::string& text, const std::string& name) {
  std::vector<Vec3<double>> raw;
  std::vector<std::array<uint32_t, 3>> tris;
  enum { kOutside, kSolid, kFacet, kLoop, kLoopDone } state = kOutside;
  int corners = 0, line_no = 0, facet_line = 0;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    ++line_no;
    const std::vector<std::string> t = tokens(line);
    if (t.empty()) continue;
    const std::string k = lower(t[0]);
    auto expect = [&](bool ok, const char* what) {
      if (!ok) fail(name, line_no, "unexpected \"" + t[0] + "\" (expected " + what + ")");
    };
    auto numbers = [&](size_t first, const char* what) {
      if (t.size() != first + 3) fail(name, line_no, std::string(what) + " needs 3 numbers, got " + std::to_string(t.size() - first));
      return make_vec3(number(t[first], name, line_no), number(t[first + 1], name, line_no), number(t[first + 2], name, line_no));
    };
    if (k == "solid") {
      expect(state == kOutside, "\"endsolid\" before another \"solid\"");
      state = kSolid;
    } else if (k == "endsolid") {
      expect(state == kSolid, state == kOutside ? "\"solid\"" : "\"endfacet\"");
      state = kOutside;
    } else if (k == "facet") {
      expect(state == kSolid, state == kOutside ? "\"solid\"" : "\"endfacet\"");
      if (t.size() < 2 || lower(t[1]) != "normal") fail(name, line_no, "expected \"facet normal nx ny nz\"");
      numbers(2, "facet normal");  // checked, not used: the winding gives the outside
      state = kFacet;
      facet_line = line_no;
    } else if (k == "outer") {
      expect(state == kFacet, "\"facet normal\" first");
      if (t.size() != 2 || lower(t[1]) != "loop") fail(name, line_no, "expected \"outer loop\"");
      state = kLoop;
      corners = 0;
    } else if (k == "vertex") {
      expect(state == kLoop, "\"outer loop\" first");
      if (++corners > 3) fail(name, line_no, "a facet with more than 3 vertices (STL facets are triangles)");
      raw.push_back(numbers(1, "vertex"));
    } else if (k == "endloop") {
      expect(state == kLoop, "\"outer loop\" first");
      if (corners != 3) fail(name, line_no, "a facet with " + std::to_string(corners) + " vertices (expected 3)");
      const uint32_t b = uint32_t(raw.size() - 3);
      tris.push_back({b, b + 1, b + 2});
      state = kLoopDone;
    } else if (k == "endfacet") {
      expect(state == kLoopDone, "\"endloop\" first");
      state = kSolid;
    } else {
      fail(name, line_no, "unexpected \"" + t[0] + "\" (an ASCII STL has solid, facet, outer loop, vertex, endloop, endfacet, endsolid)");
    }
  }
  if (state != kOutside && state != kSolid)
    fail(name, facet_line, "the file ends inside this facet (truncated?)");
  if (state == kSolid && tris.empty()) fail(name, 0, "no triangles (and no \"endsolid\")");
  return finish(raw, tris, name);
}

}  // namespace

TriangleMesh parse_stl(const std::string& bytes, const std::string& name) {
  // Binary when the size is exactly a binary STL's of the count in the header; else ASCII if
  // it starts with "solid"; else binary (and the size check says what is wrong).
  if (bytes.size() >= 84) {
    const uint64_t n = u32_le(reinterpret_cast<const unsigned char*>(bytes.data()) + 80);
    if (bytes.size() == 84 + 50 * n) return parse_binary_stl(bytes, name);
  }
  const size_t first = bytes.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && bytes.compare(first, 5, "solid") == 0 &&
      (first + 5 == bytes.size() || std::isspace(static_cast<unsigned char>(bytes[first + 5]))))
    return parse_ascii_stl(bytes, name);
  return parse_binary_stl(bytes, name);
}

TriangleMesh parse_obj(const std::string& text, const std::string& name) {
  std::vector<Vec3<double>> raw;
  std::vector<std::array<uint32_t, 3>> tris;
  struct Corner {
    long index;  // as written (positive: 1-based, resolved at the end)
    int line;
  };
  std::vector<Corner> corners;  // 3 per triangle
  std::istringstream in(text);
  int line_no = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_no;
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    const std::vector<std::string> t = tokens(line);
    if (t.empty()) continue;
    if (t[0] == "v") {
      // x y z, then an optional w (or the colours some exporters add): not used.
      if (t.size() < 4) fail(name, line_no, "a vertex needs 3 numbers, got " + std::to_string(t.size() - 1));
      raw.push_back(make_vec3(number(t[1], name, line_no), number(t[2], name, line_no), number(t[3], name, line_no)));
    } else if (t[0] == "f") {
      if (t.size() < 4) fail(name, line_no, "a face needs at least 3 vertices, got " + std::to_string(t.size() - 1));
      std::vector<long> face;
      for (size_t i = 1; i < t.size(); ++i) {
        const std::string idx = t[i].substr(0, t[i].find('/'));  // v, v/t, v//n, v/t/n: the vertex
        errno = 0;
        char* end = nullptr;
        const long v = std::strtol(idx.c_str(), &end, 10);
        if (idx.empty() || end != idx.c_str() + idx.size() || errno == ERANGE)
          fail(name, line_no, "bad vertex index \"" + t[i] + "\"");
        if (v == 0) fail(name, line_no, "vertex index 0 (OBJ counts from 1)");
        if (v < 0) {
          if (-v > long(raw.size()))
            fail(name, line_no, "vertex index " + std::to_string(v) + " out of range (" + std::to_string(raw.size()) +
                                    " vertices before it)");
          face.push_back(long(raw.size()) + v + 1);  // as a positive 1-based index
        } else {
          face.push_back(v);
        }
      }
      for (size_t i = 1; i + 1 < face.size(); ++i)  // a fan from the first corner
        for (long v : {face[0], face[i], face[i + 1]}) corners.push_back({v, line_no});
    }
    // Anything else (vt, vn, vp, o, g, s, l, usemtl, mtllib, ...): not geometry we collide with.
  }
  for (const Corner& c : corners)
    if (c.index > long(raw.size()))
      fail(name, c.line, "vertex index " + std::to_string(c.index) + " out of range (the file has " +
                             std::to_string(raw.size()) + " vertices)");
  for (size_t i = 0; i + 2 < corners.size(); i += 3)
    tris.push_back({uint32_t(corners[i].index - 1), uint32_t(corners[i + 1].index - 1), uint32_t(corners[i + 2].index - 1)});
  if (tris.empty()) fail(name, 0, "no faces (\"f\" lines): nothing to collide with");
  return finish(raw, tris, name);
}

TriangleMesh load_mesh_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, 0, "cannot read the mesh file (missing?)");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) fail(path, 0, "error while reading the mesh file");
  const std::string ext = lower(path.size() >= 4 ? path.substr(path.size() - 4) : path);
  if (ext == ".obj") return parse_obj(bytes, path);
  if (ext == ".stl") return parse_stl(bytes, path);
  fail(path, 0, "unknown mesh format (expected a .stl or .obj file)");
}

Mat3<double> MeshVolume::inertia_for_mass(double mass_kg) const {
  Mat3<double> r = inertia_mm5;
  const double density = volume_mm3 > 0 ? mass_kg / volume_mm3 : 0;
  for (auto& row : r.m)
    for (double& v : row) v *= density;
  return r;
}

MeshVolume mesh_volume(const TriangleMesh& mesh) {
  // Signed tetrahedra (origin, a, b, c): volume det/6, first moment det/24 (a + b + c),
  // second moment det/120 (a a^T + b b^T + c c^T + s s^T) with s = a + b + c.
  double V = 0, C[3][3] = {};
  Vec3<double> first = make_vec3(0.0, 0.0, 0.0);
  for (const auto& t : mesh.triangles) {
    const Vec3<double>& a = mesh.vertices[t[0]];
    const Vec3<double>& b = mesh.vertices[t[1]];
    const Vec3<double>& c = mesh.vertices[t[2]];
    const double det = dot(a, cross(b, c));
    const Vec3<double> s = a + b + c;
    V += det / 6;
    first = first + (det / 24) * s;
    const double va[3] = {a.x, a.y, a.z}, vb[3] = {b.x, b.y, b.z}, vc[3] = {c.x, c.y, c.z}, vs[3] = {s.x, s.y, s.z};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) C[i][j] += det / 120 * (va[i] * va[j] + vb[i] * vb[j] + vc[i] * vc[j] + vs[i] * vs[j]);
  }
  MeshVolume r;
  if (V < 0) {  // inside out: every term changed sign
    V = -V;
    first = -1.0 * first;
    for (auto& row : C)
      for (double& v : row) v = -v;
  }
  r.volume_mm3 = V;
  if (V > 0) {
    r.centre_mm = (1 / V) * first;
    const double c[3] = {r.centre_mm.x, r.centre_mm.y, r.centre_mm.z};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) C[i][j] -= V * c[i] * c[j];  // about the centre
    const double trace = C[0][0] + C[1][1] + C[2][2];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r.inertia_mm5.m[i][j] = (i == j ? trace : 0.0) - C[i][j];
  }
  // Closed: each directed edge once, and its reverse once.
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++edges[{t[size_t(k)], t[size_t((k + 1) % 3)]}];
  r.closed = !edges.empty();
  for (const auto& [e, n] : edges) {
    const auto back = edges.find({e.second, e.first});
    r.closed = r.closed && n == 1 && back != edges.end() && back->second == 1;
  }
  return r;
}

}  // namespace articula::host
