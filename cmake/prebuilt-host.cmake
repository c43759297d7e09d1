# The host libraries as a tree build (make) left them, for `pip install .` with
# -DARTICULA_PREBUILT_DIR=<that build's folder>: the same sources, compiled once, with the same
# flags (position-independent, for the module), linked into the wheel's module instead of
# compiled again. The wheel's test (python/tests/test_install.py) builds so, so that `make test`
# compiles nothing twice; a user's `pip install .` compiles them (host/CMakeLists.txt).
set(ARTICULA_UNITY_BUILD ON)  # (host/CMakeLists.txt's option: the module compiles in a batch)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(ODE REQUIRED IMPORTED_TARGET ode)

function(articula_prebuilt name file)
  set(path ${ARTICULA_PREBUILT_DIR}/${file})
  if(NOT EXISTS ${path})
    message(FATAL_ERROR "ARTICULA_PREBUILT_DIR=${ARTICULA_PREBUILT_DIR} has no ${file}: build the tree first (make)")
  endif()
  add_library(${name} STATIC IMPORTED GLOBAL)
  set_target_properties(${name} PROPERTIES IMPORTED_LOCATION ${path})
endfunction()

articula_prebuilt(articula_firmware_sitl host/libarticula_firmware_sitl.a)
articula_prebuilt(articula_host host/libarticula_host.a)
articula_prebuilt(articula_physics host/physics/libarticula_physics.a)
# What each one's users get, as host/CMakeLists.txt and host/physics/CMakeLists.txt say it.
set_target_properties(articula_host PROPERTIES
  INTERFACE_INCLUDE_DIRECTORIES ${PROJECT_SOURCE_DIR}/host/lib
  INTERFACE_LINK_LIBRARIES "articula::core;nlohmann_json::nlohmann_json;articula_firmware_sitl")
set_target_properties(articula_physics PROPERTIES
  INTERFACE_INCLUDE_DIRECTORIES ${PROJECT_SOURCE_DIR}/host/physics
  INTERFACE_LINK_LIBRARIES "articula_host;PkgConfig::ODE")
