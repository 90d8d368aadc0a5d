// The solver tests build their boxes of particles directly (tests/solver/
// solver_fixtures.h); the case files name this geometry because every case
// must name one.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
