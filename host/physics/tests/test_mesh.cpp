// Tests host/physics/mesh.h (STL and OBJ reading, volume and inertia) and mesh link shapes in
// host/physics/sim.h. Data (tests/data/): a 20 mm cube centred on its origin as binary STL,
// ASCII STL and OBJ (quads, with relative indices and v/t/n forms), and mesh-arm.json, the MK2
// with that cube as its last link.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <fstream>
#include <iterator>
#include <sstream>

#include "mesh.h"
#include "program.h"
#include "robot_file.h"
#include "sim.h"

using namespace articula;
using namespace articula::host;

namespace {

const std::string kData = std::string(ARTICULA_SOURCE_DIR) + "/host/physics/tests/data/";

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The triangles as coordinates, each rotated to start at its smallest corner (the winding
// kept), sorted: equal for two meshes with the same triangles whatever the vertex order.
using Tri = std::array<std::array<double, 3>, 3>;
std::vector<Tri> canonical(const TriangleMesh& m) {
  std::vector<Tri> out;
  for (const auto& t : m.triangles) {
    Tri c;
    for (int k = 0; k < 3; ++k) {
      const Vec3<double>& v = m.vertices[t[size_t(k)]];
      c[size_t(k)] = {v.x, v.y, v.z};
    }
    std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
    out.push_back(c);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// An OBJ of an axis-aligned box of sides (x, y, z) mm with its corner `at`, as six quads.
std::string box_obj(double x, double y, double z, Vec3<double> at, bool inside_out = false) {
  std::ostringstream o;
  for (int k = 0; k < 8; ++k)
    o << "v " << at.x + ((k & 1) ^ (k >> 1 & 1)) * x << ' ' << at.y + (k >> 1 & 1) * y << ' ' << at.z + (k >> 2) * z << '\n';
  // Corners 1..8: 1 (0,0,0) 2 (x,0,0) 3 (x,y,0) 4 (0,y,0), then 5..8 the same at z.
  const char* faces[] = {"1 4 3 2", "5 6 7 8", "1 2 6 5", "2 3 7 6", "3 4 8 7", "4 1 5 8"};
  const char* reversed[] = {"2 3 4 1", "8 7 6 5", "5 6 2 1", "6 7 3 2", "7 8 4 3", "8 5 1 4"};
  for (int f = 0; f < 6; ++f) o << "f " << (inside_out ? reversed[f] : faces[f]) << '\n';
  return o.str();
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const MeshError& e) {
    return e.what();
  }
  return "(no error)";
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

}  // namespace

TEST(Mesh, ThreeFormatsGiveTheSameTriangles) {
  const TriangleMesh bin = load_mesh_file(kData + "cube20.stl");
  const TriangleMesh ascii = load_mesh_file(kData + "cube20_ascii.stl");
  const TriangleMesh obj = load_mesh_file(kData + "cube20.obj");
  EXPECT_EQ(bin.vertices.size(), 8u) << "STL repeats each corner per triangle: merged";
  EXPECT_EQ(bin.triangles.size(), 12u);
  EXPECT_EQ(obj.vertices.size(), 8u);
  EXPECT_EQ(obj.triangles.size(), 12u) << "six quads, fan-triangulated";
  EXPECT_EQ(canonical(bin), canonical(ascii));
  EXPECT_EQ(canonical(bin), canonical(obj));
  for (const auto& v : bin.vertices) {
    EXPECT_EQ(std::fabs(v.x), 10.0);
    EXPECT_EQ(std::fabs(v.y), 10.0);
    EXPECT_EQ(std::fabs(v.z), 10.0);
  }
}

TEST(Mesh, BinaryStlStartingWithSolidIsStillBinary) {
  std::string bytes = read_bytes(kData + "cube20.stl");
  bytes.replace(0, 5, "solid");
  EXPECT_EQ(canonical(parse_stl(bytes, "solid.stl")), canonical(load_mesh_file(kData + "cube20.stl")));
}

TEST(Mesh, ErrorsNameTheFileTheLineAndTheProblem) {
  std::string e = error_of([] { load_mesh_file(kData + "no-such.stl"); });
  EXPECT_TRUE(contains(e, "no-such.stl") && contains(e, "cannot read")) << e;

  const std::string bin = read_bytes(kData + "cube20.stl");
  e = error_of([&] { parse_stl(bin.substr(0, 600), "cut.stl"); });
  EXPECT_TRUE(contains(e, "cut.stl: truncated binary STL") && contains(e, "12 triangles") && contains(e, "600 bytes")) << e;
  e = error_of([&] { parse_stl(bin.substr(0, 50), "tiny.stl"); });
  EXPECT_TRUE(contains(e, "tiny.stl: truncated")) << e;

  const std::string ascii = read_bytes(kData + "cube20_ascii.stl");
  std::string bad = ascii;
  bad.replace(bad.find("vertex -10 10 -10"), 17, "vertex -10 1O -10");  // letter O: line 5
  e = error_of([&] { parse_stl(bad, "bad.stl"); });
  EXPECT_TRUE(contains(e, "bad.stl: line 5: bad number \"1O\"")) << e;
  e = error_of([&] { parse_stl(ascii.substr(0, ascii.find("endloop")), "open.stl"); });
  EXPECT_TRUE(contains(e, "open.stl: line 2: the file ends inside this facet")) << e;
  e = error_of([] { parse_stl("solid x\n  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      vertex 1 0 0\n    endloop\n", "two.stl"); });
  EXPECT_TRUE(contains(e, "two.stl: line 6: a facet with 2 vertices")) << e;
  e = error_of([] { parse_stl("solid empty\nendsolid empty\n", "empty.stl"); });
  EXPECT_TRUE(contains(e, "empty.stl: no triangles")) << e;

  e = error_of([] { parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "range.obj"); });
  EXPECT_TRUE(contains(e, "range.obj: line 4: vertex index 4 out of range (the file has 3 vertices)")) << e;
  e = error_of([] { parse_obj("v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n", "neg.obj"); });
  EXPECT_TRUE(contains(e, "neg.obj: line 3: vertex index -3 out of range")) << e;
  e = error_of([] { parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "zero.obj"); });
  EXPECT_TRUE(contains(e, "zero.obj: line 4: vertex index 0")) << e;
  e = error_of([] { parse_obj("# a triangle\nv 0 0 0\nv 1 0 zero\n", "num.obj"); });
  EXPECT_TRUE(contains(e, "num.obj: line 3: bad number \"zero\"")) << e;
  e = error_of([] { parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\n", "novertex.obj"); });
  EXPECT_TRUE(contains(e, "novertex.obj: no faces")) << e;
  e = error_of([] { parse_obj("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", "flat.obj"); });
  EXPECT_TRUE(contains(e, "flat.obj: every triangle has zero area")) << e;
}

// The cube against the solid box's formulas: V = a b c, I_xx = m (b^2 + c^2) / 12 (so per
// unit density V (b^2 + c^2) / 12), products of inertia 0, the centre where it is.
TEST(Mesh, VolumeCentreAndInertiaOfABox) {
  const MeshVolume cube = mesh_volume(load_mesh_file(kData + "cube20.stl"));
  EXPECT_TRUE(cube.closed);
  EXPECT_NEAR(cube.volume_mm3, 20.0 * 20 * 20, 1e-9);
  EXPECT_NEAR(norm(cube.centre_mm), 0, 1e-12);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(cube.inertia_mm5.m[i][j], i == j ? 8000.0 * 800 / 12 : 0.0, 1e-6);
  const double m = 0.0216;  // kg: 20 mm of a 2700 kg/m^3 metal
  EXPECT_NEAR(cube.inertia_for_mass(m).m[1][1], m * 800 / 12, 1e-12);

  // A 10 x 24 x 40 box away from the origin, and the same inside out.
  for (bool inside_out : {false, true}) {
    const MeshVolume b = mesh_volume(parse_obj(box_obj(10, 24, 40, make_vec3(30.0, -50.0, 7.0), inside_out), "box.obj"));
    EXPECT_TRUE(b.closed);
    const double V = 10.0 * 24 * 40;
    EXPECT_NEAR(b.volume_mm3, V, 1e-6);
    EXPECT_NEAR(b.centre_mm.x, 35, 1e-9);
    EXPECT_NEAR(b.centre_mm.y, -38, 1e-9);
    EXPECT_NEAR(b.centre_mm.z, 27, 1e-9);
    EXPECT_NEAR(b.inertia_mm5.m[0][0], V * (24 * 24 + 40 * 40) / 12, 1e-4);
    EXPECT_NEAR(b.inertia_mm5.m[1][1], V * (10 * 10 + 40 * 40) / 12, 1e-4);
    EXPECT_NEAR(b.inertia_mm5.m[2][2], V * (10 * 10 + 24 * 24) / 12, 1e-4);
    EXPECT_NEAR(b.inertia_mm5.m[0][1], 0, 1e-4);
    EXPECT_NEAR(b.inertia_mm5.m[0][2], 0, 1e-4);
    EXPECT_NEAR(b.inertia_mm5.m[1][2], 0, 1e-4);
  }
  // Without one face it is not closed.
  std::string open = box_obj(10, 10, 10, make_vec3(0.0, 0.0, 0.0));
  open.erase(open.rfind("f "));
  EXPECT_FALSE(mesh_volume(parse_obj(open, "open.obj")).closed);
}

namespace {

Robot mesh_arm() { return load_robot_file(kData + "mesh-arm.json"); }

// The same robot with the mesh replaced by the box it is.
Robot box_arm() {
  Robot r = mesh_arm();
  for (auto& l : r.links)
    for (auto& s : l.shapes)
      if (s.type == Shape::Type::kMesh) {
        s.type = Shape::Type::kBox;
        s.size = {20, 20, 20};
        s.mesh.clear();
      }
  return r;
}

std::vector<const SimEvent*> of_kind(const Simulation& sim, SimEvent::Kind k) {
  std::vector<const SimEvent*> out;
  for (const auto& e : sim.events())
    if (e.kind == k) out.push_back(&e);
  return out;
}

double sim_tolerance_mm() { return SimOptions{}.touch_tolerance_mm; }

dGeomID geom_of(const Simulation& sim, int frame) {
  for (const auto& p : sim.arm_parts())
    if (p.frame == frame) return dBodyGetFirstGeom(p.body);
  return nullptr;
}

}  // namespace

TEST(MeshSim, AMissingMeshFileNamesTheRobotFileAndTheShape) {
  Robot r = mesh_arm();
  r.links[3].shapes[0].mesh = "gone.stl";
  try {
    Simulation sim(r, Scene{});
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_TRUE(contains(m, "mesh-arm.json: /links/3/shapes/0: ") && contains(m, "gone.stl") && contains(m, "cannot read")) << m;
  }
}

// The mesh link's body rides on its DH frame, and its trimesh sits at the shape's xyz in it.
TEST(MeshSim, MeshLinkFramesEqualDhFrames) {
  const Robot r = mesh_arm();
  const Program p = parse_protocol_program("M 30 60 -20\nM -10 120 10\nM 0 90 0\n", "frames.arm", r);
  Simulation sim(r, Scene{});
  sim.load_program(p);
  const Prediction pr = predict_program(r, p);
  const dGeomID g = geom_of(sim, 4);
  ASSERT_NE(g, nullptr);
  ASSERT_EQ(dGeomGetClass(g), dTriMeshClass);
  for (const PredictRecord& rec : pr.records) {
    ASSERT_EQ(rec.reply, kOk);
    sim.run_until(rec.end_s() + 0.002);
    std::vector<double> q(size_t(r.model.num_joints));
    joints_from_steps(q.data(), r.actuation, rec.steps.data());
    HostFrames f;
    forward_kinematics(f, r.model, q.data());
    const Transform<double> T = f.T_base_frame[4] * r.links[3].shapes[0].T_frame_shape;
    const dReal* pos = dGeomGetPosition(g);
    const dReal* R = dGeomGetRotation(g);
    EXPECT_NEAR(pos[0], T.p.x / 1000, 1e-6) << "line " << rec.line;
    EXPECT_NEAR(pos[1], T.p.y / 1000, 1e-6);
    EXPECT_NEAR(pos[2], T.p.z / 1000, 1e-6);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) EXPECT_NEAR(R[i * 4 + j], T.R.m[i][j], 1e-9);
  }
  EXPECT_TRUE(of_kind(sim, SimEvent::Kind::kCollision).empty());
}

// Lowered onto the ground, the mesh cube stops where the box cube stops: the same collision
// event, the same steps lost, the same pose.
TEST(MeshSim, GroundStopsAMeshLinkLikeTheBox) {
  std::vector<int32_t> lost[2];
  std::vector<double> q[2];
  SimEvent hit[2];
  int i = 0;
  for (const Robot& r : {mesh_arm(), box_arm()}) {
    Simulation sim(r, Scene{});
    sim.load_program(parse_protocol_program("M 0 36 -43\n", "down.arm", r));
    while (!sim.done()) sim.step();
    const auto hits = of_kind(sim, SimEvent::Kind::kCollision);
    ASSERT_EQ(hits.size(), 1u) << (i ? "box" : "mesh");
    hit[i] = *hits[0];
    lost[i] = sim.lost_steps();
    q[i] = sim.joints();
    dReal aabb[6];
    dGeomGetAABB(geom_of(sim, 4), aabb);
    EXPECT_GE(aabb[4] * 1000, -sim.options().touch_tolerance_mm - 1e-9) << "held at contact";
    EXPECT_LT(aabb[4] * 1000, 1.0) << "but down to the ground";
    ++i;
  }
  EXPECT_EQ(hit[0].a, "link 4");
  EXPECT_EQ(hit[0].b, "ground");
  EXPECT_EQ(hit[0].a, hit[1].a);
  EXPECT_EQ(hit[0].t, hit[1].t);
  // The point is a corner of the cube the refused step would have put below the ground.
  EXPECT_LE(hit[0].point_mm.z, 0);
  EXPECT_GE(hit[0].point_mm.z, -hit[0].depth_mm - 1e-6);
  EXPECT_GT(hit[0].depth_mm, sim_tolerance_mm());
  EXPECT_NEAR(std::hypot(hit[0].point_mm.x - hit[1].point_mm.x, hit[0].point_mm.y - hit[1].point_mm.y), 0, 20 * std::sqrt(2.0))
      << "on the same cube";
  EXPECT_NEAR(hit[0].depth_mm, hit[1].depth_mm, 1e-6);
  EXPECT_NE(lost[0], std::vector<int32_t>(3, 0));
  EXPECT_EQ(lost[0], lost[1]);
  EXPECT_EQ(q[0], q[1]);
}

// Swept through a box on the ground, the mesh cube pushes it as the box cube does.
TEST(MeshSim, AMeshLinkPushesABoxLikeTheBox) {
  Scene scene;
  SceneObject box;
  box.name = "box";
  box.size = {30, 30, 30};
  box.xyz = make_vec3(263.0, 0.0, 15.0);  // where the cube passes at shoulder 45, elbow motor -43
  box.movable = true;
  box.mass = 0.027;
  scene.objects.push_back(box);
  double moved[2];
  int i = 0;
  for (const Robot& r : {mesh_arm(), box_arm()}) {
    Simulation sim(r, scene);
    sim.load_program(parse_protocol_program("L 0 -30\nM -30 45 -43\nL 0 60\n", "sweep.arm", r));
    const Vec3<double> p0 = sim.object_pose(0).p;
    while (!sim.done()) sim.step();
    const Vec3<double> p1 = sim.object_pose(0).p;
    moved[i] = std::hypot(p1.x - p0.x, p1.y - p0.y);
    bool touched = false;
    for (const SimEvent* e : of_kind(sim, SimEvent::Kind::kContactStarted)) touched = touched || (e->a == "box" && e->b == "link 4");
    EXPECT_TRUE(touched) << (i ? "box" : "mesh");
    EXPECT_TRUE(of_kind(sim, SimEvent::Kind::kCollision).empty());
    EXPECT_FALSE(sim.object_removed(0));
    EXPECT_GT(p1.z, 10);
    ++i;
  }
  EXPECT_GT(moved[0], 30) << "the mesh pushed the box";
  EXPECT_NEAR(moved[0], moved[1], 0.15 * moved[1]) << "as far as the box cube does";
}

// The stall model needs a mesh's mass (host/lib/mass.h); a robot without pull-out curves has
// no stall check and needs none.
TEST(MeshSim, AMeshNeedsAMassOnlyForTheStallCheck) {
  Robot r = mesh_arm();
  r.links[3].shapes[0].mass = 0;
  EXPECT_NO_THROW(Simulation(r, Scene{}));
  r.motor_torque.assign(3, MotorTorque{});
  r.motor_torque[1].pull_out = {{{0, 0.4}}, {{1000, 0.2}}};
  try {
    Simulation sim(r, Scene{});
    FAIL() << "no error";
  } catch (const RobotFileError& e) {
    const std::string m = e.what();
    EXPECT_TRUE(contains(m, "/links/3/shapes/0") && contains(m, "mass")) << m;
  }
  r.links[3].shapes[0].mass = 0.01;
  EXPECT_NO_THROW(Simulation(r, Scene{}));
}

// What libode's build can do with a mesh (docs/physics.md): the cube mesh 0.5 mm into each
// shape gives the overlap as depth, like the cube as a box; mesh against mesh collides but
// its depth is not the overlap (the reason for the note below).
TEST(MeshSim, OdeCollidesAMeshWithEveryShape) {
  dInitODE2(0);
  const TriangleMesh cube = load_mesh_file(kData + "cube20.stl");
  std::vector<dReal> v;
  std::vector<dTriIndex> idx;
  for (const auto& p : cube.vertices)
    for (double c : {p.x, p.y, p.z}) v.push_back(c / 1000);
  for (const auto& t : cube.triangles)
    for (uint32_t i : t) idx.push_back(i);
  dTriMeshDataID data = dGeomTriMeshDataCreate();
  dGeomTriMeshDataBuildDouble(data, v.data(), 3 * sizeof(dReal), int(v.size() / 3), idx.data(), int(idx.size()),
                              3 * sizeof(dTriIndex));
  dGeomID mesh = dCreateTriMesh(nullptr, data, nullptr, nullptr, nullptr);
  dGeomID mesh2 = dCreateTriMesh(nullptr, data, nullptr, nullptr, nullptr);
  struct Other {
    const char* name;
    dGeomID g;
    double top;  // its top above its centre, m
  } others[] = {{"ground", dCreatePlane(nullptr, 0, 0, 1, 0), 0},
                {"box", dCreateBox(nullptr, 0.02, 0.02, 0.02), 0.01},
                {"sphere", dCreateSphere(nullptr, 0.01), 0.01},
                {"capsule", dCreateCapsule(nullptr, 0.01, 0.02), 0.02},
                {"cylinder", dCreateCylinder(nullptr, 0.01, 0.02), 0.01},
                {"mesh", mesh2, 0.01}};
  const double overlap = 0.0005;
  dGeomSetPosition(mesh, 0.002, 0.001, 0.01 - overlap);  // its bottom 0.5 mm below z = 0
  for (const Other& o : others) {
    if (o.top > 0) dGeomSetPosition(o.g, 0, 0, -o.top);  // its top at z = 0
    dContactGeom c[32];
    const int n = dCollide(mesh, o.g, 32, c, sizeof(dContactGeom));
    EXPECT_GT(n, 0) << o.name;
    double depth = 0;
    for (int i = 0; i < n; ++i) depth = std::max(depth, double(c[i].depth));
    if (o.g != mesh2) {
      EXPECT_NEAR(depth, overlap, 1e-9) << o.name;
    } else {
      EXPECT_GT(depth, 10 * overlap) << "ODE gives a mesh pair a true depth now: docs/physics.md and the note can go";
    }
  }
  for (const Other& o : others) dGeomDestroy(o.g);
  dGeomDestroy(mesh);
  dGeomTriMeshDataDestroy(data);  // ODE stays initialised: the simulations of other tests share it
}

TEST(MeshSim, TwoMeshPartsGiveANote) {
  Robot r = mesh_arm();
  r.links[1].shapes[0] = r.links[3].shapes[0];  // the cube on the upper arm too
  r.links[1].shapes[0].T_frame_shape = Transform<double>::identity();
  Simulation sim(r, Scene{});
  int notes = 0;
  for (const SimEvent* e : of_kind(sim, SimEvent::Kind::kNote)) notes += contains(e->detail, "mesh against mesh");
  EXPECT_EQ(notes, 1);
}
