// bench/bench_scene.h - the physics benchmarks' scene: the MK2 arm and a 3 cm cube on the
// ground, and about 9 s of moves over the whole working range (bench_physics, bench_engine).
#ifndef ARTICULA_BENCH_SCENE_H
#define ARTICULA_BENCH_SCENE_H

#include "scene.h"

namespace articula::bench {

inline host::Scene cube_scene() {
  host::Scene s;
  host::SceneObject cube;
  cube.name = "cube";
  cube.size = {30, 30, 30};
  cube.xyz = make_vec3(250.0, -60.0, 15.0);
  cube.movable = true;
  cube.mass = 0.027;  // 30 mm of wood-like plastic
  s.objects.push_back(cube);
  return s;
}

// About 9 s of moves over the whole working range, then rest until 10 s.
inline const char* const kMoves =
    "G 100\nM 40 60 -30\nM -40 100 10\nG 0\nM 0 45 -40\nM 60 80 -20\nG 60\nM -60 50 0\nM 0 120 -40\n"
    "M 30 36 -43\nM -30 90 15\nG 100\nM 0 90 0\n";

}  // namespace articula::bench

#endif  // ARTICULA_BENCH_SCENE_H
