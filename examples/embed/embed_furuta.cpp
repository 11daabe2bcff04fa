// embed_furuta.cpp - a C++ program that embeds the generated Furuta pendulum through its CMake
// package (furuta::furuta).  The arm is driven by a constant torque of 0.01 N m from the pendulum
// 0.2 rad off upright; one call of the emitted RK4 per 1 ms control period for 1 s, as a control
// loop would.  Prints phi'' at the start and the state every 0.25 s, 17 significant digits.
#include <array>
#include <cstdio>

#include "furuta.h"

int main()
{
    std::array<double, 2 * FURUTA_N> x = {{0.0, 3.141592653589793 - 0.2, 0.0, 0.0}};
    const std::array<double, FURUTA_NU> u = {{0.01}};
    std::array<double, FURUTA_N> qdd{};
    if (furuta_qdd(x.data(), u.data(), nullptr, qdd.data()) != FURUTA_OK) {
        std::fprintf(stderr, "furuta_qdd failed\n");
        return 1;
    }
    std::printf("qdd %.17g %.17g\n", qdd[0], qdd[1]);
    const double h = 1e-3;
    for (int step = 1; step <= 1000; ++step) {
        long n_rhs = 0;
        const int code = furuta_integrate(FURUTA_RK4, (step - 1) * h, step * h, h, 0.0, 0.0, x.data(), u.data(),
                                          nullptr, x.data(), &n_rhs);
        if (code != FURUTA_OK) {
            std::fprintf(stderr, "furuta_integrate failed with code %d at step %d\n", code, step);
            return 1;
        }
        if (step % 250 == 0) {
            std::printf("t %.3f x %.17g %.17g %.17g %.17g\n", step * h, x[0], x[1], x[2], x[3]);
        }
    }
    return 0;
}
