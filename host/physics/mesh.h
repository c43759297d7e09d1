// host/physics/mesh.h - triangle meshes for link shapes of type "mesh" (robots/README.md):
// binary STL, ASCII STL and Wavefront OBJ, and the volume, centre and inertia of a closed one.
//
// Units: a mesh file has none, so its coordinates are taken as millimetres, like every length
// in a robot file (export from CAD in mm). The mesh is used as it is in the file, placed by
// the shape's xyz/rpy: its own origin is the shape's origin.
//
// What is read:
//   - STL: binary (80-byte header, triangle count, 50 bytes a triangle) or ASCII
//     (`solid` ... `facet normal` / `outer loop` / 3 x `vertex x y z` / `endloop` / `endfacet`
//     ... `endsolid`). A file whose size is exactly that of a binary STL of the count in its
//     header is binary, even if it starts with "solid" (many exporters write that header).
//     The normals are not used (the winding gives the outside).
//   - OBJ: `v x y z [w]` and `f i j k ...` lines (1-based indices, negative ones counted back
//     from the last vertex read, `i/t/n` forms accepted); a polygon is fan-triangulated from
//     its first vertex; every other line (vt, vn, o, g, s, usemtl, comments) is ignored.
// Equal vertices (bit for bit, as STL repeats them per triangle) are merged; triangles that
// collapse to a line or a point are dropped (they have no normal, no area).
//
// Errors (MeshError) name the file, the line for text formats, and the problem: a missing
// file, a truncated binary STL, a bad number, an index out of range, no triangles.
#ifndef ARTICULA_PHYSICS_MESH_H
#define ARTICULA_PHYSICS_MESH_H

#include <articula/transform.h>

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace articula::host {

class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct TriangleMesh {
  std::vector<Vec3<double>> vertices;             // mm
  std::vector<std::array<uint32_t, 3>> triangles;  // indices into vertices, counter-clockwise seen from outside
};

// Reads `path`: an OBJ when the name ends in .obj (any case), else an STL (binary or ASCII
// by its content). Messages name the file as `path` is written.
TriangleMesh load_mesh_file(const std::string& path);
// The same from bytes already read: an STL (binary or ASCII) or an OBJ.
TriangleMesh parse_stl(const std::string& bytes, const std::string& name);
TriangleMesh parse_obj(const std::string& text, const std::string& name);

// Volume properties of a closed mesh as a solid of uniform density, by the divergence
// theorem: a signed tetrahedron from the origin to each triangle (volume det/6, centroid the
// mean of its four corners, second moment det/120 (sum v v^T + (sum v)(sum v)^T) over its three
// vertices). An inside-out mesh (clockwise winding) gives the same figures as the right one.
struct MeshVolume {
  double volume_mm3 = 0;
  Vec3<double> centre_mm{0, 0, 0};
  // The inertia about the centre, axes of the mesh, per unit density: mm^5. Times a density
  // in kg/mm^3 it is kg*mm^2; inertia_for_mass() does that for a given mass.
  Mat3<double> inertia_mm5{{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
  bool closed = false;  // every edge shared by exactly two triangles in opposite directions
  // kg*mm^2 for a body of `mass_kg` spread uniformly over the volume.
  Mat3<double> inertia_for_mass(double mass_kg) const;
};
MeshVolume mesh_volume(const TriangleMesh& mesh);

}  // namespace articula::host

#endif  // ARTICULA_PHYSICS_MESH_H
