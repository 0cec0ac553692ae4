# The Constellations' libFuzzer targets (docs/fuzzing.md, "An element's own targets"): the GL-free
# file readers they feed, relative to this element's folder. Read by tests/fuzz/CMakeLists.txt
# with -DWELKIN_FUZZ=ON only.
set(WELKIN_FUZZ_ELEMENT_SOURCES src/constellation_files.cpp)
