// The BSDF suite's chi-square harness, compiled into this suite too (one harness for every
// model; the file itself stays in tests/native/bsdf).
#include "../bsdf/chi_square.cpp"
