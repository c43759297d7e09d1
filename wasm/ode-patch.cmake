# ODE 0.16.2 (Debian's source package) for WebAssembly: two lines of its build do not know
# emscripten. Run as the patch step of the ODE build in wasm/CMakeLists.txt, on the unpacked
# source (-DODE_SOURCE=...); idempotent.
#  - config.h.cmake.in identifies the platform and stops with "Need some help identifying the
#    platform!" for anything it does not know: emscripten's libc is POSIX, take the Linux branch.
#  - CMakeLists.txt sets PENTIUM when CMAKE_SYSTEM_PROCESSOR looks like x86 (emscripten's
#    toolchain file says "x86"), which pulls x86 inline assembly into timer.cpp.
#  - and, for the unity build wasm/CMakeLists.txt asks (every em++ call costs a second before
#    it compiles anything: ODE's hundred files took 210 CPU s), the sources that reuse each
#    other's names compile alone: OPCODE and its Ice, the trimesh colliders, and the
#    threading helpers beside them.
function(patch file from to)
  file(READ ${file} text)
  string(FIND "${text}" "${to}" done)
  if(done GREATER -1)
    return()
  endif()
  string(FIND "${text}" "${from}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "ode-patch: '${from}' is not in ${file}: another ODE version? (expected 0.16.2)")
  endif()
  string(REPLACE "${from}" "${to}" text "${text}")
  file(WRITE ${file} "${text}")
endfunction()

patch(${ODE_SOURCE}/config.h.cmake.in "#elif defined(__linux__)"
      "#elif defined(__linux__) || defined(__EMSCRIPTEN__)")
patch(${ODE_SOURCE}/CMakeLists.txt "if(CMAKE_SYSTEM_PROCESSOR MATCHES \"i686.*|x86.*|x86_64.*|amd64.*|AMD64.*\")"
      "if(NOT EMSCRIPTEN AND CMAKE_SYSTEM_PROCESSOR MATCHES \"i686.*|x86.*|x86_64.*|amd64.*|AMD64.*\")")
patch(${ODE_SOURCE}/CMakeLists.txt "add_library(ODE \${SRCS})\n"
      "add_library(ODE \${SRCS})\n# (Articula's patch) alone in a unity build: these reuse each other's names\nforeach(s \${SRCS})\n  if(s MATCHES \"OPCODE|trimesh|/ou/|odeou|odetls\")\n    set_source_files_properties(\${s} PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)\n  endif()\nendforeach()\n")
