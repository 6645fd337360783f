// solve_field: magnetostatic FEM of the configured magnet (docs/interfaces.md).
//   solve_field [--config F.toml] [--set key=value]... [--out DIR]
// Writes DIR/mesh.vtu, plane.vti, box.vti, solve.json (all or nothing).
// Distributed: mpirun -n N solve_field ... (fem.solver = petsc-hypre, the
// default when built with PETSc) solves the linear systems across N ranks.
#include <CLI/CLI.hpp>
#include <iostream>

#include "core/atomic_output.hpp"
#include "core/cli.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "field_solver/solve/fem_config.hpp"
#include "field_solver/solve/linear_solver.hpp"
#include "field_solver/field_io/field_outputs.hpp"
#include "field_solver/solve/magnetostatic_solver.hpp"

int main(int argc, char** argv) {
  return magenc::run_main("solve_field", [&] {
    const auto schema = magenc::fem::solve_field_schema();
    CLI::App app{"Magnetostatic FEM of a diametrically magnetized cylindrical magnet: writes plane.vti, box.vti, solve.json (and mesh.vtu with output.mesh_vtu)"};
    magenc::CommonOptions opts;
    magenc::add_common_options(app, opts, schema);
    // Every rank parses the command line, so --help and flag errors end all
    // ranks alike (before MPI starts).
    magenc::parse_cli(app, argc, argv);
    // Under mpirun (fem.solver = petsc-*): ranks > 0 only take part in the
    // linear solves of rank 0, which reads the configuration, meshes,
    // assembles and writes (linear_solver.hpp). Without mpirun: one rank.
    magenc::fem::MpiSession mpi;
    if (mpi.rank() > 0) {
      mpi.serve();
      return 0;
    }
    const magenc::Config cfg = magenc::load_config(schema, opts);
    const auto settings = magenc::fem::fem_settings_from_config(cfg);
    // 1. Output directory first, so that a bad --out fails before the solve.
    magenc::AtomicDir out(opts.out.empty() ? "output/field" : opts.out);
    // 2. Mesh, assemble, solve.
    magenc::fem::MagnetostaticSolver solver(settings.domain, settings.solver);
    solver.run();
    // 3. Outputs, then commit.
    magenc::fem::write_field_outputs(out.path(), settings, solver, cfg.to_json());
    out.commit();
    const auto& st = solver.stats();
    const std::string solved =
        st.solved_dofs != st.dofs ? " (" + std::to_string(st.solved_dofs) + " solved on the symmetry quadrant)" : "";
    std::cerr << "solve_field: P" << st.order << ", " << st.elements << " elements, " << st.dofs << " dofs" << solved << ", "
              << st.iterations << " CG iterations (residual " << magenc::fmt_sig(st.residual, 3) << "), " << magenc::fmt(st.t_total_s, 2)
              << " s; wrote " << out.final_path().string() << "\n";
    return 0;
  });
}
