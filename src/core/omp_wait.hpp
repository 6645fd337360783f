// OpenMP waiting policy for programs that run many small parallel regions (diagnose's fits: thousands of
// model evaluations of ~1e3 field points each). libgomp's default lets idle threads spin; on a machine whose
// cores are busy with other work (other builds), a spinning thread takes the time slice its team-mate needs
// and every barrier then costs a scheduler quantum: measured 2.7 s instead of 0.4 s for one fit under load
// ~11 on 2 cores. libgomp reads OMP_WAIT_POLICY only at start-up, so
// prefer_passive_omp_wait() re-executes the program once with OMP_WAIT_POLICY=passive when the variable is
// unset (a user's explicit setting is kept). Call it first thing in main().
#pragma once

namespace magenc {

void prefer_passive_omp_wait(int argc, char** argv);

}  // namespace magenc
