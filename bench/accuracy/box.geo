// The chart runs build their particle lattices directly (bench/accuracy_run.c);
// the case file names this geometry because every case must name one.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
