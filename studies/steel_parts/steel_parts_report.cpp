#include "studies/steel_parts/steel_parts_report.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include "core/format.hpp"
#include "io/plot.hpp"
#include "report/study_plots.hpp"

namespace magenc {

namespace {

std::string g10(double v) { return fmt_sig(v, 10); }
std::string label(const SteelPartsSolve& s) { return s.model == "-" ? s.variant : s.variant + " (" + s.model + ")"; }
std::string mT_text(double v) { return std::isinf(v) ? std::string("inf") : fmt(v, 1); }

const SteelPartsCase* find_case(const SteelPartsResult& r, const SteelPartsSolve& s, const std::string& array,
                                const std::string& mount) {
  for (const auto& c : r.cases)
    if (c.variant == s.variant && c.model == s.model && c.array == array && c.mount_label == mount) return &c;
  return nullptr;
}

}  // namespace

std::string steel_parts_cases_csv(const SteelPartsResult& r) {
  std::ostringstream os;
  os << "variant,model,array,case,sx_mm,sy_mm,dx_mm,dy_mm,pp_deg,a0_deg,c1_deg,c2_deg,c3_deg,c4_deg,field_min_mT,"
        "field_max_mT,in_window\n";
  for (const auto& c : r.cases)
    os << c.variant << "," << c.model << "," << c.array << "," << c.mount_label << "," << g10(c.mount.sx_mm) << ","
       << g10(c.mount.sy_mm) << "," << g10(c.mount.dx_mm) << "," << g10(c.mount.dy_mm) << "," << g10(c.spectrum.pp_deg)
       << "," << g10(c.spectrum.a0_deg) << "," << g10(c.spectrum.c_deg[1]) << "," << g10(c.spectrum.c_deg[2]) << ","
       << g10(c.spectrum.c_deg[3]) << "," << g10(c.spectrum.c_deg[4]) << "," << g10(c.field_min_mT) << ","
       << g10(c.field_max_mT) << "," << (c.in_window ? "true" : "false") << "\n";
  return os.str();
}

std::string steel_parts_solves_csv(const SteelPartsResult& r) {
  std::ostringstream os;
  os << "variant,model,material,potential,dofs,elements,nonlinear_iterations,newton_steps,final_residual,"
        "linear_iterations,t_solve_s,part_B_max_T,part_mu_r_min\n";
  for (const auto& s : r.solves)
    os << s.variant << "," << s.model << "," << s.material << "," << s.potential << "," << s.dofs << "," << s.elements
       << "," << s.nonlinear_iterations << "," << s.newton_steps << ","
       << (s.nonlinear_residuals.empty() ? std::string() : g10(s.nonlinear_residuals.back())) << ","
       << s.linear_iterations << "," << g10(s.t_solve_s) << "," << g10(s.part_B_max_T) << "," << g10(s.part_mu_r_min)
       << "\n";
  return os.str();
}

void write_steel_parts_report(StudyOutput& out, const SteelPartsResult& r) {
  // 1. Tables.
  out.write_text("steel_parts.csv", steel_parts_cases_csv(r));
  out.write_text("solves.csv", steel_parts_solves_csv(r));
  // 2. Plots: the field on the plane, the harmonics.
  {
    PlotSpec ps;
    ps.title = "Bz along x on the sensing plane (z = " + fmt(r.plane_z_mm, 2) + " mm); red: the field window";
    ps.width_px = 1200;
    ps.height_px = 700;
    PlotPanel p;
    p.xlabel = "x [mm]";
    p.ylabel = "B_z [mT]";
    for (const auto& s : r.solves) {
      const bool dashed = s.model == "nonlinear";
      p.series.push_back({plot_literal(label(s)), s.profile_x_mm, s.profile_Bz_mT, "lines", dashed ? "lw 2 dt 2" : "lw 2"});
    }
    p.commands = {"set grid", "set key outside right"};
    for (double w : {r.window.min_mT, r.window.max_mT})
      if (w > 0 && std::isfinite(w))
        for (double sgn : {1.0, -1.0})
          p.commands.push_back("set arrow from graph 0, first " + fmt_sig(sgn * w, 6) + " to graph 1, first " +
                               fmt_sig(sgn * w, 6) + " nohead lw 1 lc rgb 'red'");
    p.commands.push_back("set arrow from " + fmt_sig(r.r0_mm, 6) + ", graph 0 to " + fmt_sig(r.r0_mm, 6) +
                         ", graph 1 nohead lw 1 dt 3 lc rgb 'black'");
    ps.panels.push_back(p);
    write_plot(out.dir(), "profile", ps);
  }
  {
    const std::string array = r.arrays.front();
    PlotSpec ps;
    ps.title = "Angle-error harmonics, array " + plot_literal(array) + ", one offset of " + fmt(r.offset_mm, 2) + " mm";
    ps.columns = 2;
    ps.width_px = 1600;
    ps.height_px = 700;
    for (const char* m : {"sx", "dx"}) {
      std::vector<SpectrumCase> cs;
      for (const auto& s : r.solves)
        if (const SteelPartsCase* c = find_case(r, s, array, m)) cs.push_back({plot_literal(label(s)), c->spectrum});
      PlotPanel p = harmonics_panel(std::string(m) + " = " + fmt(r.offset_mm, 2) + " mm", cs, false);
      p.commands.push_back("set xrange [0.5:4.5]");
      ps.panels.push_back(p);
    }
    write_plot(out.dir(), "harmonics", ps);
  }
  // 3. summary.md.
  std::ostringstream md;
  md << "# steel_parts: what steel and brass around the magnet do to the field and the harmonics\n\n## What ran\n\n";
  md << "- Magnet R = " << fmt(r.magnet_radius_mm, 2) << " mm, L = " << fmt(r.magnet_height_mm, 2) << " mm, Br = "
     << fmt(r.br_T, 2) << " T; sensing plane z = " << fmt(r.plane_z_mm, 2) << " mm; r0 = " << fmt(r.r0_mm, 2)
     << " mm; field window " << mT_text(r.window.min_mT) << " .. " << mT_text(r.window.max_mT) << " mT.\n";
  md << "- Steel: linear `" << r.linear_material << "` (mu_r = " << fmt_sig(r.linear_mu_r, 4) << ")";
  if (!r.bh_file.empty()) md << "; nonlinear: the B-H curve `" << r.bh_file << "` (Newton)";
  md << ". Brass: mu_r = 1.\n";
  md << "- Mounting cases: ideal, and each of sx, sy, dx, dy alone at " << fmt(r.offset_mm, 3) << " mm.\n\n";
  md << "## Solves\n\n| solve | part | potential | dofs | nonlinear iterations (Newton) | final residual | max abs(B) in the part [T] | min mu_r in the part | time [s] |\n";
  md << "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |\n";
  for (const auto& s : r.solves)
    md << "| " << label(s) << " | " << (s.parts.empty() ? "-" : s.parts) << " | " << s.potential << " | " << s.dofs
       << " | " << (s.nonlinear_iterations ? std::to_string(s.nonlinear_iterations) + " (" + std::to_string(s.newton_steps) + ")" : "-")
       << " | " << (s.nonlinear_residuals.empty() ? "-" : fmt_sig(s.nonlinear_residuals.back(), 2)) << " | "
       << (s.parts.empty() ? "-" : fmt(s.part_B_max_T, 3)) << " | "
       << (s.parts.empty() ? "-" : fmt_sig(s.part_mu_r_min, 4)) << " | " << fmt(s.t_solve_s, 1) << " |\n";
  for (const auto& array : r.arrays) {
    md << "\n## Array " << array << ": field window (ideal mount) and c1..c4 [deg]\n\n";
    md << "| solve | field min..max [mT] | in window | ideal c1 | ideal c2 | ideal c4 | sx c1 | sx c2 | sx c3 | dx c1 | dx c2 | dx c3 | pp (sx) |\n";
    md << "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
    for (const auto& s : r.solves) {
      const SteelPartsCase* id = find_case(r, s, array, "ideal");
      const SteelPartsCase* sx = find_case(r, s, array, "sx");
      const SteelPartsCase* dx = find_case(r, s, array, "dx");
      if (!id || !sx || !dx) continue;
      md << "| " << label(s) << " | " << fmt(id->field_min_mT, 1) << " .. " << fmt(id->field_max_mT, 1) << " | "
         << (id->in_window ? "yes" : "**no**") << " | " << fmt_sig(id->spectrum.c_deg[1], 2) << " | "
         << fmt_sig(id->spectrum.c_deg[2], 2) << " | " << fmt_sig(id->spectrum.c_deg[4], 2) << " | "
         << fmt(sx->spectrum.c_deg[1], 4) << " | " << fmt(sx->spectrum.c_deg[2], 4) << " | " << fmt(sx->spectrum.c_deg[3], 4)
         << " | " << fmt(dx->spectrum.c_deg[1], 4) << " | " << fmt(dx->spectrum.c_deg[2], 4) << " | "
         << fmt(dx->spectrum.c_deg[3], 4) << " | " << fmt(sx->spectrum.pp_deg, 4) << " |\n";
    }
  }
  md << "\nEvery case of every array and offset: `steel_parts.csv`; the solves: `solves.csv`; plots `profile.png`, "
        "`harmonics.png`. Under the ideal mount a linear coaxial part keeps the magnet's symmetry: its harmonics are "
        "the mesh's (zero to the solver tolerance below the mesh's symmetry order). A saturating part does not keep "
        "the field's pure cos(phi) form: its permeability follows |H|, which varies around the part, and the field "
        "gains higher azimuthal terms (ideal-mount c4 of the saturating cup).\n";
  if (!r.field_files_dir.empty())
    md << "\nField files of the " << r.field_files_solve << " solve for ParaView, in `" << r.field_files_dir
       << "/`: `bodies.vtu` (the magnet's and the cup's cells with B, region, mu_r) and `slice_y0.vti` (B [T] on the "
          "plane y = 0 through the axis, step "
       << fmt(r.slice_step_mm, 2) << " mm); written in " << fmt(r.t_field_files_s, 2)
       << " s. State: `paraview_states/steel_parts_B.pvsm`.\n";
  out.write_text("summary.md", md.str());
}

}  // namespace magenc
