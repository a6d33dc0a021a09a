// robust_sphere.h as a user vendors it: robust_sphere_test copies the header
// alone (with answers.h) into an empty directory and builds this file against
// it with strict warnings and FMA contraction allowed (-mfma
// -ffp-contract=fast), so the double path's TwoProduct runs on std::fma.
// Reads cases "ox oy oz dx dy dz cx cy cz r tmin tmax" (C99 hex floats), one
// a line, and prints each one's answers in float, then double; the test
// compares them with the library build's, which the oracle checks.
#include <cstdio>

#include "answers.h"

int main() {
    double v[12];
    while (std::scanf("%la %la %la %la %la %la %la %la %la %la %la %la", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5],
                      &v[6], &v[7], &v[8], &v[9], &v[10], &v[11]) == 12)
        std::printf("%s\n%s\n", robust_answers<float>(v).c_str(), robust_answers<double>(v).c_str());
    return 0;
}
