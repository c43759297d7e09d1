# ODE 0.16.2 (Debian's source package) for WebAssembly: two lines of its build do not know
# emscripten. Run as the patch step of the ODE build in wasm/CMakeLists.txt, on the unpacked
# source (-DODE_SOURCE=...); idempotent.
#  - config.h.cmake.in identifies the platform and stops with "Need some help identifying the
#    platform!" for anything it does not know: emscripten's libc is POSIX, take the Linux branch.
#  - CMakeLists.txt sets PENTIUM when CMAKE_SYSTEM_PROCESSOR looks like x86 (emscripten's
#    toolchain file says "x86"), which pulls x86 inline assembly into timer.cpp.
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
