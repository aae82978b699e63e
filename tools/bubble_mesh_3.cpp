// bubble_mesh_3: the command-line front end of the Bubble_mesh_3 package.
//
// Exit codes: 0 success, 2 invalid input or usage (one line on stderr),
// 3 meshing or internal failure, 4 --time-limit reached, 130 interrupted
// (SIGINT). Only 0 leaves a mesh; files are written atomically.
#include <CGAL/Bubble_mesh_3/IO/cross_section_svg.h>
#include <CGAL/Bubble_mesh_3/IO/medit.h>
#include <CGAL/Bubble_mesh_3/IO/read_triangle_surface.h>
#include <CGAL/Bubble_mesh_3/detect_features.h>
#include <CGAL/Bubble_mesh_3/IO/sol.h>
#include <CGAL/Bubble_mesh_3/IO/vtu.h>
#include <CGAL/Bubble_mesh_3/IO/write_file_atomically.h>
#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Bubble_mesh_3/Quality_report.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/metric_quality.h>
#include <CGAL/Bubble_mesh_3/validity.h>
#include <CGAL/Bubble_mesh_3/internal/surface_fidelity.h>
#include <CGAL/Bubble_mesh_3/analytic_metric_fields.h>
#include <CGAL/Constant_metric_field_3.h>
#include <CGAL/Function_metric_field_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Interpolated_metric_field_3.h>
#include <CGAL/Graded_metric_field_3.h>
#include <CGAL/Hessian_metric_field_3.h>
#include <CGAL/Bubble_mesh_3/remesh_anisotropic_3.h>
#include <CGAL/Realizable_metric_field_3.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/boost/graph/copy_face_graph.h>
#include <CGAL/make_anisotropic_mesh_3.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <iomanip>

#include <cerrno>
#include <csignal>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

// a constant field's frame never turns (make_realizable_metric_field_3 returns it as it is)
template <typename F>
struct Is_constant_field : std::false_type {};
template <typename K>
struct Is_constant_field<CGAL::Constant_metric_field_3<K>> : std::true_type {};

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
using CGAL::Bubble_mesh_3::Indexed_tet_mesh_3;
using CGAL::Bubble_mesh_3::Invalid_input;
using CGAL::Bubble_mesh_3::Metric_3;
namespace BIO = CGAL::Bubble_mesh_3::IO;

// SIGINT sets a flag that the mesher polls at its check points (it then
// throws Interrupted and nothing is written); a second SIGINT kills at once.
volatile std::sig_atomic_t interrupt_requested = 0;
extern "C" void on_sigint(int)
{
  interrupt_requested = 1;
  std::signal(SIGINT, SIG_DFL);
}
const int exit_time_limit = 4;
const int exit_interrupted = 130;

const char* const usage_text =
    "bubble_mesh_3 - anisotropic tetrahedral meshing by ellipsoidal bubble packing\n"
    "\n"
    "Usage:\n"
    "  bubble_mesh_3 SURFACE -o OUT.mesh [METRIC] [--vtu OUT.vtu] [--feature-angle DEG]\n"
    "                [--min-feature-length L] [--report R.json] [--histogram H.svg] [--seed S] [--threads N]\n"
    "                [--max-nodes N] [--section S.svg [--section-plane x|y|z=VALUE]]\n"
    "                [--time-limit SECONDS] [--no-small-feature-refinement] [--no-realizable-metric]\n"
    "                [--no-improve] [--quiet]\n"
    "      Mesh the volume inside a closed triangle surface (OFF, OBJ, STL, PLY):\n"
    "      bubble packing on corners, sharp feature curves (edges whose faces meet\n"
    "      at more than DEG degrees from flat, default 60; a crease with a free end\n"
    "      shorter than L elements in the metric, default 1, is dropped: it separates\n"
    "      no patches and its corners would be nodes closer than an element; a patch\n"
    "      narrower than a tenth of an element joins a 4x wider neighbour; 0 keeps\n"
    "      all, as CGAL's detect_features), surface patches and the\n"
    "      interior (where corners and curves are closer to each other than the\n"
    "      metric's size it is refined to their distance, and where the part is\n"
    "      thinner than it to the thickness, growing by half the distance away\n"
    "      from them; --no-small-feature-refinement keeps it as given; where an\n"
    "      anisotropic metric's frame turns faster than straight edges of its\n"
    "      large sizes can follow, as a boundary layer around a curved wall,\n"
    "      those sizes are reduced until they can: --no-realizable-metric keeps\n"
    "      them), then an anisotropic advancing front, then metric flips and\n"
    "      smoothing of the worst tets (--no-improve: skip). Progress goes to stderr,\n"
    "      a summary (nodes, tets, times, metric quality) to stdout. Without a\n"
    "      METRIC the size is 1/20 of the bounding box diagonal. The mesh (MEDIT,\n"
    "      with boundary patches, feature edges and corners) is written only when\n"
    "      it is complete and valid. --max-nodes refuses larger node estimates\n"
    "      before any work (default 5e6, about 10 GB). --time-limit stops the run\n"
    "      (exit 4, no file) when it is reached before the front is done; the\n"
    "      improvement is cut to the time left instead. Ctrl-C (SIGINT) stops it\n"
    "      at the next check point (exit 130, no file). Input checks: see\n"
    "      doc/Bubble_mesh_3/input_checks.md. --section draws the tets cut by a\n"
    "      plane (default: y through the centre of the bounding box) coloured by\n"
    "      metric quality.\n"
    "      Exit 3 when no valid mesh could be made.\n"
    "  bubble_mesh_3 eval MESH.mesh [METRIC] [--report R.json] [--vtu OUT.vtu]\n"
    "                [--histogram H.svg] [--title TEXT] [--surface S] [--quiet] [--require-valid]\n"
    "      Quality report of any tetrahedral mesh in MEDIT format (also from TetGen\n"
    "      or CGAL Mesh_3): metric minimum dihedral angles (worst, 1st percentile,\n"
    "      mean, 5-degree histogram), metric mean ratios (the UGAWG shape measure:\n"
    "      worst, 1st percentile, mean), metric edge lengths, inverted tets, volume,\n"
    "      and validity (orientation, conformity, boundary, volume identity).\n"
    "      --require-valid exits with 2 when the mesh is not valid.\n"
    "      --report writes it as JSON, --vtu writes the mesh with per-tet quality,\n"
    "      --histogram writes an SVG histogram. --surface S compares the boundary\n"
    "      with the closed surface S that was meshed: volume error, largest distance\n"
    "      of the boundary to S (sampled over each triangle) and of S's vertices to\n"
    "      the boundary, as the meshing report gives them.\n"
    "  bubble_mesh_3 convert IN.mesh OUT.{vtu,mesh}\n"
    "      Convert a MEDIT mesh to VTU (ParaView) or rewrite it as MEDIT.\n"
    "  bubble_mesh_3 adapt IN.mesh --solution U.sol (--error E | --target-vertices N) -o OUT.mesh\n"
    "                [--norm P] [--hmin A] [--hmax B] [--max-ratio R] [--gradation BETA]\n"
    "                [--feature-angle DEG] [--interpolate-solution OUT.sol] [--metric-out M.sol]\n"
    "                [--report R.json] [--vtu OUT.vtu] [--seed S] [--threads N] [--max-nodes N]\n"
    "                [--surface-distance D|auto|off] [--time-limit SECONDS] [--no-improve] [--quiet]\n"
    "      A new mesh of the domain of IN.mesh (MEDIT) for the interpolation error of\n"
    "      the scalar solution U.sol (MEDIT, SolAtVertices type 1, one value per\n"
    "      vertex of IN.mesh): Hessian recovered by a quadratic fit on vertex rings,\n"
    "      metric M = (9/32)|H|/E (L-infinity error E), or scaled for about N\n"
    "      vertices (L^P-optimal, P default 2); sizes within [A, B] (default diagonal\n"
    "      x 1e-4 and / 10), anisotropy <= R (default 1000). --gradation bounds the\n"
    "      growth of the metric: sizes grow at most by 1 + l ln(BETA) over metric\n"
    "      length l (anisotropic, directions kept; default 1.5, 'off': none; the\n"
    "      target N counts the vertices it adds). The boundary of IN.mesh is the\n"
    "      surface meshed (edges between triangle references are feature curves);\n"
    "      boundary and subdomain references are carried over; it stays within D of\n"
    "      the input's boundary (default auto: the diagonal / 200; as for meshing).\n"
    "      --interpolate-solution\n"
    "      writes U interpolated (P1) at the new vertices; --metric-out the metric at\n"
    "      the vertices of IN.mesh.\n"
    "  bubble_mesh_3 --help | --version\n"
    "\n"
    "METRIC (default: identity, i.e. unit isotropic size):\n"
    "  --size H                            isotropic metric of element size H\n"
    "  --metric-const a11,a12,a13,a22,a23,a33\n"
    "                                      constant symmetric positive definite metric\n"
    "  --metric-mesh BG.mesh --metric-sol BG.sol\n"
    "                                      metric at the vertices of a background tet mesh\n"
    "                                      (SolAtVertices, type 3: m11 m21 m22 m31 m32 m33),\n"
    "                                      log-Euclidean interpolation, nearest value outside\n"
    "  --metric-cylindrical PX,PY,PZ,DX,DY,DZ,H,RATIO,R\n"
    "                                      size H along and across the axis through P along D,\n"
    "                                      tangential size growing from H on the axis to\n"
    "                                      RATIO*H at distance R (the paper's 1:1 to 1:3)\n"
    "  --metric-boundary-layer HN,HT,T     (meshing only) tangential size HT, size HN normal\n"
    "                                      to the input surface on it, growing to HT at depth T\n"
    "  --metric-ugawg CASE[,SCALE]         an analytic metric of the UGAWG benchmark: linear\n"
    "                                      (unit cube, 1:100 layer at z = 0.5), polar-1\n"
    "                                      (cube-cylinder, 1:100 layer on the wall r = 0.5) or\n"
    "                                      polar-2 (polar-1, tangential size refined near the wall),\n"
    "                                      every size times SCALE (default 1)\n"
    "  --surface-distance D|auto|off       (meshing) keep the boundary within D of the input\n"
    "                                      surface: near it the metric is intersected with sizes\n"
    "                                      sqrt(3 D / |k|) along the principal curvature\n"
    "                                      directions (auto: D = bounding box diagonal / 200;\n"
    "                                      default off; quality is then measured in that\n"
    "                                      intersected metric)\n"
    "\n"
    "Quality is the minimum dihedral angle of each tet after mapping it by Q,\n"
    "M(centroid) = Q^T Q. Edge lengths are in the metric; the target is 1.\n"
    "\n"
    "Exit codes: 0 success, 2 invalid input or usage, 3 meshing or internal failure,\n"
    "4 time limit reached, 130 interrupted (SIGINT).\n";

// Usage errors are invalid input too: one line, exit 2.
struct Usage_error : Invalid_input {
  explicit Usage_error(const std::string& what) : Invalid_input(what) {}
};

// Options as a map from "--name" to value; flags map to "".
struct Options {
  std::vector<std::string> positional;
  std::map<std::string, std::string> values;

  bool has(const std::string& name) const { return values.count(name) != 0; }
  std::string get(const std::string& name) const
  {
    auto it = values.find(name);
    return it == values.end() ? std::string() : it->second;
  }
};

Options parse_options(int argc, char** argv, int first, const std::vector<std::string>& with_value,
                      const std::vector<std::string>& flags)
{
  Options o;
  for(int i = first; i < argc; ++i) {
    std::string a = argv[i];
    if(a.size() > 1 && a[0] == '-' && a != "-") {
      bool takes_value = std::find(with_value.begin(), with_value.end(), a) != with_value.end();
      bool is_flag = std::find(flags.begin(), flags.end(), a) != flags.end();
      if(!takes_value && !is_flag)
        throw Usage_error("unknown option '" + a + "' (see bubble_mesh_3 --help)");
      if(o.has(a))
        throw Usage_error("option '" + a + "' given twice");
      if(takes_value) {
        if(i + 1 >= argc)
          throw Usage_error("option '" + a + "' needs a value");
        o.values[a] = argv[++i];
      } else {
        o.values[a] = "";
      }
    } else {
      o.positional.push_back(a);
    }
  }
  return o;
}

double parse_number(const std::string& text, const std::string& what)
{
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if(text.empty() || end != text.c_str() + text.size() || errno == ERANGE)
    throw Usage_error(what + ": '" + text + "' is not a number");
  return v;
}

// The last component of a path (descriptions stay short in plots and summaries).
std::string file_name(const std::string& path)
{
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

// The metric field chosen on the command line. Kept behind one small
// interface so that every subcommand evaluates the same way.
class Command_line_metric {
public:
  static std::vector<double> numbers(const Options& o, const std::string& name, std::size_t count,
                                     const std::string& format)
  {
    std::vector<double> a;
    std::stringstream ss(o.get(name));
    for(std::string item; std::getline(ss, item, ',');)
      a.push_back(parse_number(item, name));
    if(a.size() != count)
      throw Usage_error(name + " needs " + std::to_string(count) + " comma-separated numbers " + format + ", got " +
                        std::to_string(a.size()));
    return a;
  }

  static Command_line_metric from_options(const Options& o, double default_size = 0,
                                          const CGAL::Surface_mesh<K::Point_3>* surface = nullptr)
  {
    Command_line_metric m;
    const int given = int(o.has("--size")) + int(o.has("--metric-const")) +
                      int(o.has("--metric-mesh") || o.has("--metric-sol")) + int(o.has("--metric-cylindrical")) +
                      int(o.has("--metric-boundary-layer")) + int(o.has("--metric-ugawg"));
    if(given > 1)
      throw Usage_error("give at most one of --size, --metric-const, --metric-mesh/--metric-sol, "
                        "--metric-cylindrical, --metric-boundary-layer, --metric-ugawg");
    if(o.has("--metric-cylindrical")) {
      const std::vector<double> a = numbers(o, "--metric-cylindrical", 9, "PX,PY,PZ,DX,DY,DZ,H,RATIO,R");
      const CGAL::Bubble_mesh_3::Cylindrical_metric c(Eigen::Vector3d(a[0], a[1], a[2]),
                                                      Eigen::Vector3d(a[3], a[4], a[5]), a[6], a[7], a[8]);
      m.function_.emplace(Function([c](const K::Point_3& p) { return c(p); }));
      m.description_ = "cylindrical " + o.get("--metric-cylindrical");
    } else if(o.has("--metric-ugawg")) {
      const std::string value = o.get("--metric-ugawg");
      const std::size_t comma = value.find(',');
      const double scale = comma == std::string::npos ? 1.0 : parse_number(value.substr(comma + 1), "--metric-ugawg");
      const CGAL::Bubble_mesh_3::Ugawg_metric u(
          CGAL::Bubble_mesh_3::Ugawg_metric::kind_from_name(value.substr(0, comma)), scale);
      m.function_.emplace(Function([u](const K::Point_3& p) { return u(p); }));
      m.description_ = "UGAWG " + value;
    } else if(o.has("--metric-boundary-layer")) {
      const std::vector<double> a = numbers(o, "--metric-boundary-layer", 3, "HN,HT,T");
      if(surface == nullptr)
        throw Usage_error("--metric-boundary-layer needs the input surface (meshing only)");
      const CGAL::Bubble_mesh_3::Boundary_layer_metric<K> b(*surface, a[0], a[1], a[2]);
      m.function_.emplace(Function([b](const K::Point_3& p) { return b(p); }));
      m.description_ = "boundary layer " + o.get("--metric-boundary-layer");
    } else if(o.has("--size")) {
      const double h = parse_number(o.get("--size"), "--size");
      m.constant_ = CGAL::Constant_metric_field_3<K>(Metric_3::isotropic(h, "--size"));
      m.description_ = "isotropic size " + o.get("--size");
    } else if(o.has("--metric-const")) {
      std::vector<double> a;
      std::stringstream ss(o.get("--metric-const"));
      for(std::string item; std::getline(ss, item, ',');)
        a.push_back(parse_number(item, "--metric-const"));
      if(a.size() != 6)
        throw Usage_error("--metric-const needs 6 comma-separated numbers a11,a12,a13,a22,a23,a33, got " +
                          std::to_string(a.size()));
      m.constant_ = CGAL::Constant_metric_field_3<K>(
          Metric_3::from_entries(a[0], a[1], a[2], a[3], a[4], a[5], "--metric-const"));
      m.description_ = "constant " + o.get("--metric-const");
    } else if(o.has("--metric-mesh") || o.has("--metric-sol")) {
      if(!o.has("--metric-mesh") || !o.has("--metric-sol"))
        throw Usage_error("--metric-mesh and --metric-sol go together");
      m.interpolated_.emplace(
          CGAL::Interpolated_metric_field_3<K>::from_files(o.get("--metric-mesh"), o.get("--metric-sol")));
      if(surface != nullptr)
        m.note_ = coverage_note(*m.interpolated_, *surface, o.get("--metric-mesh"));
      m.description_ = "interpolated from " + file_name(o.get("--metric-mesh")) + " + " +
                       file_name(o.get("--metric-sol"));
    } else if(default_size > 0) {
      m.constant_ = CGAL::Constant_metric_field_3<K>(Metric_3::isotropic(default_size, "default size"));
      std::ostringstream d;
      d << "isotropic size " << default_size << " (default: bounding box diagonal / 20)";
      m.description_ = d.str();
    } else {
      m.description_ = "identity";
    }
    return m;
  }

  template <typename F>
  auto visit(F&& f) const
  {
    if(interpolated_)
      return f(*interpolated_);
    if(function_)
      return f(*function_);
    return f(constant_);
  }

  const std::string& description() const { return description_; }
  /// a warning for the progress output (empty if none)
  const std::string& note() const { return note_; }

private:
  // Outside the background mesh the nearest vertex's metric is used (the
  // field is extended); say how much of the surface that concerns, and
  // refuse a background mesh that misses the domain altogether.
  static std::string coverage_note(const CGAL::Interpolated_metric_field_3<K>& field,
                                   const CGAL::Surface_mesh<K::Point_3>& surface, const std::string& path)
  {
    const CGAL::Bbox_3 bg = field.bbox();
    const CGAL::Bbox_3 domain = CGAL::Polygon_mesh_processing::bbox(surface);
    if(!CGAL::do_overlap(bg, domain))
      throw Invalid_input(path + ": the background mesh does not overlap the domain (its bounding box is disjoint "
                                 "from the surface's)");
    const std::size_t outside = field.number_of_points_outside(surface.points());
    if(outside == 0)
      return std::string();
    return "warning: " + std::to_string(outside) + " of " + std::to_string(surface.number_of_vertices()) +
           " surface vertices lie outside the background mesh " + file_name(path) +
           "; the metric of the nearest background vertex is used there";
  }

  CGAL::Constant_metric_field_3<K> constant_;
  std::optional<CGAL::Interpolated_metric_field_3<K>> interpolated_;
  typedef std::function<Metric_3(const K::Point_3&)> Function;
  std::optional<CGAL::Function_metric_field_3<K, Function>> function_;
  std::string description_;
  std::string note_;
};

bool ends_with(const std::string& s, const std::string& suffix)
{
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// the boundary of `mesh` against the closed surface in `path` (triangles
// listed twice, as CGAL's output_to_medit writes them, counted once)
CGAL::Bubble_mesh_3::internal::Surface_fidelity surface_fidelity_of(const Indexed_tet_mesh_3& mesh,
                                                                    const std::string& path)
{
  const CGAL::Surface_mesh<K::Point_3> surface = BIO::read_triangle_surface<K>(path);
  CGAL::Bubble_mesh_3::internal::front::Boundary_surface input;
  for(auto v : surface.vertices()) {
    const K::Point_3& p = surface.point(v);
    input.points.push_back({{p.x(), p.y(), p.z()}});
  }
  for(auto f : surface.faces()) {
    std::array<int, 3> t;
    int k = 0;
    for(auto v : vertices_around_face(surface.halfedge(f), surface))
      t[std::size_t(k++)] = int(v);
    input.triangles.push_back(t);
  }
  Indexed_tet_mesh_3 boundary;
  boundary.points = mesh.points;
  std::set<std::array<int, 3>> seen;
  for(const auto& t : mesh.triangles) {
    std::array<int, 3> key = t;
    std::sort(key.begin(), key.end());
    if(seen.insert(key).second)
      boundary.triangles.push_back(t);
  }
  if(boundary.triangles.empty())
    throw Invalid_input("eval --surface: the mesh has no boundary triangles to compare with " + path);
  return CGAL::Bubble_mesh_3::internal::surface_fidelity(input, boundary);
}

int run_eval(int argc, char** argv)
{
  const Options o = parse_options(argc, argv, 2,
                                  {"--size", "--metric-const", "--metric-mesh", "--metric-sol", "--metric-cylindrical",
                                   "--metric-ugawg", "--report", "--vtu", "--histogram", "--title", "--surface"},
                                  {"--quiet", "--require-valid"});
  if(o.positional.size() != 1)
    throw Usage_error("eval needs exactly one MESH.mesh argument (see bubble_mesh_3 --help)");
  const std::string mesh_path = o.positional[0];
  const Command_line_metric metric = Command_line_metric::from_options(o);
  const Indexed_tet_mesh_3 mesh = BIO::read_medit(mesh_path);
  if(mesh.tets.empty())
    throw Invalid_input(mesh_path + ": the mesh has no tetrahedra");

  CGAL::Bubble_mesh_3::Quality_report report =
      metric.visit([&](const auto& field) { return CGAL::Bubble_mesh_3::compute_quality_report(mesh, field); });
  report.metric_description = metric.description();

  CGAL::Bubble_mesh_3::Validity_options validity_options;
  validity_options.allow_unused_vertices = true;     // reported, not fatal, when evaluating
  validity_options.allow_duplicate_triangles = true; // CGAL's output_to_medit lists each facet twice
  const CGAL::Bubble_mesh_3::Validity_report validity = CGAL::Bubble_mesh_3::check_validity(mesh, validity_options);
  // how far the boundary is from the surface meshed (any mesher's, by the
  // same code as the meshing report's)
  std::optional<CGAL::Bubble_mesh_3::internal::Surface_fidelity> fidelity;
  if(o.has("--surface"))
    fidelity = surface_fidelity_of(mesh, o.get("--surface"));

  if(!o.has("--quiet")) {
    CGAL::Bubble_mesh_3::print_quality_summary(std::cout, report);
    CGAL::Bubble_mesh_3::print_validity_summary(std::cout, validity);
    if(fidelity)
      std::cout << "Surface " << o.get("--surface") << ": volume error " << 100 * fidelity->volume_error
                << " %, largest distance of the boundary to it " << fidelity->mesh_to_surface << " ("
                << fidelity->mesh_to_surface / fidelity->diagonal << " of its diagonal), of its vertices to the boundary "
                << fidelity->surface_to_mesh << "\n";
  }
  if(o.has("--report")) {
    std::string json = CGAL::Bubble_mesh_3::to_json(report);
    json.insert(json.rfind("\n}"), ",\n  \"validity\": " + CGAL::Bubble_mesh_3::to_json(validity));
    if(fidelity) {
      auto num = [](double x) { return CGAL::Bubble_mesh_3::internal::format_json_number(x); };
      json.insert(json.rfind("\n}"), ",\n  \"surface\": {\"volume_error\": " + num(fidelity->volume_error) +
                                         ", \"surface_distance\": " + num(fidelity->mesh_to_surface) +
                                         ", \"surface_distance_relative\": " +
                                         num(fidelity->mesh_to_surface / fidelity->diagonal) +
                                         ", \"input_to_boundary_distance\": " + num(fidelity->surface_to_mesh) + "}");
    }
    BIO::write_text_file(o.get("--report"), json + "\n");
  }
  if(o.has("--histogram")) {
    const std::string title = o.has("--title") ? o.get("--title") : mesh_path;
    CGAL::Bubble_mesh_3::write_histogram_svg(o.get("--histogram"), report, title);
  }
  if(o.has("--vtu")) {
    std::vector<double> quality = metric.visit(
        [&](const auto& field) { return CGAL::Bubble_mesh_3::metric_minimum_dihedral_angles(mesh, field); });
    BIO::write_vtu(o.get("--vtu"), mesh, {{"min_dihedral", quality}});
  }
  if(o.has("--require-valid") && !validity.is_valid())
    throw Invalid_input(mesh_path + ": invalid mesh, " + std::to_string(validity.number_of_problems) +
                        " problem(s); first: " + validity.problems.front());
  return 0;
}

int run_convert(int argc, char** argv)
{
  const Options o = parse_options(argc, argv, 2, {}, {});
  if(o.positional.size() != 2)
    throw Usage_error("convert needs IN.mesh OUT.vtu (or OUT.mesh)");
  const Indexed_tet_mesh_3 mesh = BIO::read_medit(o.positional[0]);
  const std::string& out = o.positional[1];
  if(ends_with(out, ".vtu"))
    BIO::write_vtu(out, mesh);
  else if(ends_with(out, ".mesh"))
    BIO::write_medit(out, mesh);
  else
    throw Usage_error("convert: output '" + out + "' must end in .vtu or .mesh");
  return 0;
}

// --surface-distance D|auto|off: D, -1 (auto: a fraction of the diagonal) or 0
double parse_surface_distance(const Options& o, double fallback)
{
  if(!o.has("--surface-distance"))
    return fallback;
  const std::string v = o.get("--surface-distance");
  if(v == "off")
    return 0.0;
  if(v == "auto")
    return -1.0;
  const double d = parse_number(v, "--surface-distance");
  if(!(d > 0))
    throw Usage_error("--surface-distance must be a positive length, 'auto' or 'off'");
  return d;
}

int parse_count(const std::string& text, const std::string& what)
{
  const double v = parse_number(text, what);
  if(!(v >= 0) || v != std::floor(v) || v > 1e9)
    throw Usage_error(what + ": '" + text + "' is not a non-negative integer");
  return static_cast<int>(v);
}

// One line per stage on stderr, with the seconds since this call (nothing
// when quiet).
std::function<void(const std::string&)> progress_printer(bool quiet)
{
  const auto t0 = std::chrono::steady_clock::now();
  return [quiet, t0](const std::string& message) {
    if(quiet)
      return;
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::ostringstream line;
    line << "[" << std::fixed << std::setprecision(1) << std::setw(7) << t << " s] " << message << "\n";
    std::cerr << line.str();
  };
}

// Runs a meshing; a failure or a stop is reported on one line and becomes
// the exit code (0: the mesh was made; nothing is written otherwise).
template <typename Run>
int exit_code_of_meshing(const Run& run)
{
  namespace BM = CGAL::Bubble_mesh_3;
  try {
    run();
  } catch(const BM::Meshing_failure& e) {
    std::cerr << "bubble_mesh_3: meshing failed: " << e.what() << "\n";
    return 3;
  } catch(const BM::Time_limit_exceeded& e) {
    std::cerr << "bubble_mesh_3: " << e.what() << " (--time-limit); nothing written\n";
    return exit_time_limit;
  } catch(const BM::Interrupted& e) {
    std::cerr << "bubble_mesh_3: " << e.what() << " (SIGINT); nothing written\n";
    return exit_interrupted;
  }
  return 0;
}

// The pipeline's options common to the mesh and adapt commands (SIGINT stops it).
auto meshing_parameters(unsigned seed, int threads, double max_nodes, CGAL::Bubble_mesh_3::Meshing_report& report,
                        bool improve, double time_limit, const std::function<void(const std::string&)>& progress)
{
  return CGAL::Bubble_mesh_3::parameters::random_seed(seed)
      .number_of_threads(threads)
      .maximum_number_of_bubbles(max_nodes)
      .meshing_report(&report)
      .mesh_improvement(improve)
      .time_limit(time_limit)
      .should_stop(std::function<bool()>([] { return interrupt_requested != 0; }))
      .progress_messages(progress);
}

int run_mesh(int argc, char** argv)
{
  typedef CGAL::Polyhedral_mesh_domain_with_features_3<K> Domain;
  namespace BM = CGAL::Bubble_mesh_3;
  const Options o = parse_options(argc, argv, 1,
                                  {"-o", "--vtu", "--size", "--metric-const", "--metric-mesh", "--metric-sol",
                                   "--metric-cylindrical", "--metric-boundary-layer", "--metric-ugawg", "--surface-distance", "--section", "--section-plane",
                                   "--feature-angle", "--min-feature-length", "--report", "--histogram", "--seed", "--threads", "--max-nodes",
                                   "--time-limit"},
                                  {"--quiet", "--no-improve", "--no-small-feature-refinement", "--no-realizable-metric"});
  if(o.positional.size() != 1)
    throw Usage_error("give exactly one SURFACE file (see bubble_mesh_3 --help)");
  const bool small_features = !o.has("--no-small-feature-refinement");
  const bool realizable = !o.has("--no-realizable-metric");
  if(!o.has("-o"))
    throw Usage_error("missing -o OUT.mesh");
  const std::string out = o.get("-o");
  if(!ends_with(out, ".mesh"))
    throw Usage_error("-o: '" + out + "' must end in .mesh");
  if(o.has("--vtu") && !ends_with(o.get("--vtu"), ".vtu"))
    throw Usage_error("--vtu: '" + o.get("--vtu") + "' must end in .vtu");
  const double angle = o.has("--feature-angle") ? parse_number(o.get("--feature-angle"), "--feature-angle") : 60.0;
  if(!(angle >= 0 && angle <= 180))
    throw Usage_error("--feature-angle must be between 0 and 180 degrees");
  const double min_feature_length =
      o.has("--min-feature-length") ? parse_number(o.get("--min-feature-length"), "--min-feature-length") : 1.0;
  if(!(min_feature_length >= 0))
    throw Usage_error("--min-feature-length must be a number >= 0");
  const unsigned seed = o.has("--seed") ? unsigned(parse_count(o.get("--seed"), "--seed")) : 0u;
  const int threads = o.has("--threads") ? parse_count(o.get("--threads"), "--threads") : 0;
  const double max_nodes = o.has("--max-nodes") ? parse_number(o.get("--max-nodes"), "--max-nodes")
                                                : BM::default_maximum_number_of_nodes;
  if(!(max_nodes > 0))
    throw Usage_error("--max-nodes must be positive");
  const double time_limit = o.has("--time-limit") ? parse_number(o.get("--time-limit"), "--time-limit")
                                                  : std::numeric_limits<double>::infinity();
  if(!(time_limit > 0))
    throw Usage_error("--time-limit must be a positive number of seconds");
  const bool quiet = o.has("--quiet");
  if(o.has("--section") && !ends_with(o.get("--section"), ".svg"))
    throw Usage_error("--section: '" + o.get("--section") + "' must end in .svg");
  if(o.has("--section-plane") && !o.has("--section"))
    throw Usage_error("--section-plane goes with --section");
  std::optional<BIO::Section_plane> section_plane;
  if(o.has("--section-plane")) {
    const std::string t = o.get("--section-plane");
    if(t.size() < 3 || (t[0] != 'x' && t[0] != 'y' && t[0] != 'z') || t[1] != '=')
      throw Usage_error("--section-plane: '" + t + "' is not of the form x=VALUE, y=VALUE or z=VALUE");
    section_plane = BIO::Section_plane{t[0] - 'x', parse_number(t.substr(2), "--section-plane")};
  }
  const double surface_distance = parse_surface_distance(o, 0.0); // default off
  const std::function<void(const std::string&)> progress = progress_printer(quiet);

  const std::string surface_path = o.positional[0];
  BIO::Surface_check_report checks;
  const CGAL::Surface_mesh<K::Point_3> surface = BIO::read_triangle_surface<K>(surface_path, &checks);
  Domain::Polyhedron polyhedron;
  CGAL::copy_face_graph(surface, polyhedron);
  const CGAL::Bbox_3 bb = CGAL::Polygon_mesh_processing::bbox(surface);
  const double diagonal = std::sqrt(CGAL::square(bb.xmax() - bb.xmin()) + CGAL::square(bb.ymax() - bb.ymin()) +
                                    CGAL::square(bb.zmax() - bb.zmin()));
  progress("read " + file_name(surface_path) + ": " + std::to_string(surface.number_of_vertices()) + " vertices, " +
           std::to_string(surface.number_of_faces()) + " triangles, " + std::to_string(checks.components) +
           (checks.components == 1 ? " component" : " components") +
           (checks.cavities > 0 ? " (cavities: " + std::to_string(checks.cavities) + ")" : std::string()));
  if(checks.reoriented_faces)
    progress("repaired: faces of " + file_name(surface_path) + " reoriented consistently");
  if(checks.reversed_components > 0)
    progress("repaired: " + std::to_string(checks.reversed_components) + " component(s) of " +
             file_name(surface_path) + " reversed (outer boundaries face out, cavities in)");
  const Command_line_metric metric = Command_line_metric::from_options(o, diagonal / 20, &surface);
  progress("metric: " + metric.description());
  if(!metric.note().empty())
    progress(metric.note());
  // features at the size meshed: creases with a free end shorter than
  // --min-feature-length elements are dropped (0: CGAL's detect_features)
  BM::Detected_features<K::Point_3> features;
  metric.visit([&](const auto& field) {
    features = BM::detect_features(
        polyhedron, field, BM::parameters::feature_angle(angle).minimum_feature_length(min_feature_length));
  });
  Domain domain(polyhedron);
  features.add_to(domain);
  {
    const BM::Feature_detection_report& f = features.report;
    progress("features: " + std::to_string(f.curves) + " curves, " + std::to_string(f.corners) + " corners, " +
             std::to_string(f.patches) + " patches" +
             (f.dropped_chains > 0 ? "; dropped " + std::to_string(f.dropped_chains) +
                                         " creases with a free end shorter than " + [&] { std::ostringstream t; t << min_feature_length; return t.str(); }() +
                                         " element(s) (" + std::to_string(f.dropped_edges) + " of " +
                                         std::to_string(f.sharp_edges) + " sharp edges)"
                                   : std::string()) +
             (f.replaced_faces > 0 ? "; flipped or collapsed " + std::to_string(f.replaced_faces) +
                                         " sliver triangles narrower than a tenth of an element"
                                   : std::string()) +
             (f.merged_patches > 0 ? "; merged " + std::to_string(f.merged_patches) +
                                         " patches narrower than a tenth of an element into a neighbour (" +
                                         std::to_string(f.merged_edges) + " sharp edges no longer sharp)"
                                   : std::string()));
  }

  std::string description = metric.description();

  BM::Meshing_report meshing;
  Indexed_tet_mesh_3 mesh;
  BM::Quality_report quality;
  std::vector<double> per_tet;
  const int failed = exit_code_of_meshing([&] {
    metric.visit([&](const auto& given_field) {
      // the user's, with large sizes reduced where its frame turns too fast for them
      const auto user_field = CGAL::make_realizable_metric_field_3(given_field, realizable);
      // the field meshed (and measured): the user's, intersected near the
      // surface with the curvature sizes of the distance bound
      const auto approximating = CGAL::make_surface_approximation_metric_field_3(domain, user_field, surface_distance);
      if(approximating.bounded()) {
        std::ostringstream d;
        d << metric.description() << " with surface distance " << approximating.distance();
        description = d.str();
        progress("metric near the surface: curvature sizes for a distance bound of " +
                 std::to_string(approximating.distance()));
      }
      if(realizable && !Is_constant_field<std::decay_t<decltype(given_field)>>::value)
        description += ", large sizes limited where its frame turns";
      // refined where corners and curves are closer than its sizes
      const auto field = small_features ? CGAL::make_feature_size_metric_field_3(domain, approximating)
                                        : CGAL::Feature_size_metric_field_3<std::decay_t<decltype(approximating)>>(approximating);
      if(field.refines())
        description += ", refined at small features";
      mesh = BM::make_indexed_anisotropic_mesh_3(
          domain, field,
          meshing_parameters(seed, threads, max_nodes, meshing, !o.has("--no-improve"), time_limit, progress));
      quality = BM::compute_quality_report(mesh, field);
      if(o.has("--vtu") || o.has("--section"))
        per_tet = BM::metric_minimum_dihedral_angles(mesh, field);
      return 0;
    });
  });
  if(failed != 0)
    return failed;
  quality.metric_description = description;
  // An interrupt after the meshing stops before the next file; the files
  // already written are complete.
  auto check_interrupt = [&] {
    if(interrupt_requested)
      throw BM::Interrupted("interrupted while writing the outputs");
  };
  check_interrupt();
  BIO::write_medit(out, mesh);
  progress("wrote " + out);
  check_interrupt();
  if(o.has("--vtu")) {
    BIO::write_vtu(o.get("--vtu"), mesh, {{"min_dihedral", per_tet}});
    progress("wrote " + o.get("--vtu"));
  }
  check_interrupt();
  if(o.has("--section")) {
    const BIO::Section_plane plane =
        section_plane ? *section_plane : BIO::Section_plane{1, 0.5 * (bb.ymin() + bb.ymax())};
    BIO::write_cross_section_svg(o.get("--section"), mesh, plane, per_tet,
                                 file_name(surface_path) + ", " + description);
    progress("wrote " + o.get("--section"));
  }
  check_interrupt();
  if(o.has("--report")) {
    std::string json = BM::to_json(quality);
    json.insert(json.rfind("\n}"), ",\n  \"meshing\": " + BM::to_json(meshing));
    json.insert(json.rfind("\n}"), ",\n  \"features\": " + BM::to_json(features.report));
    BIO::write_text_file(o.get("--report"), json + "\n");
  }
  if(o.has("--histogram"))
    BM::write_histogram_svg(o.get("--histogram"), quality, file_name(surface_path) + ", " + description);
  if(!quiet) {
    BM::print_meshing_summary(std::cout, meshing);
    BM::print_quality_summary(std::cout, quality);
  }
  return 0;
}

// bubble_mesh_3 adapt: a new mesh of the domain of IN.mesh for the Hessian
// metric of a scalar solution on it (one step of a solution-adaptive loop).
int run_adapt(int argc, char** argv)
{
  namespace BM = CGAL::Bubble_mesh_3;
  const Options o = parse_options(argc, argv, 2,
                                  {"-o", "--solution", "--error", "--target-vertices", "--norm", "--hmin", "--hmax",
                                   "--max-ratio", "--gradation", "--feature-angle", "--interpolate-solution",
                                   "--metric-out", "--report", "--vtu", "--seed", "--threads", "--max-nodes",
                                   "--time-limit", "--surface-distance"},
                                  {"--quiet", "--no-improve"});
  if(o.positional.size() != 1)
    throw Usage_error("adapt needs exactly one IN.mesh argument (see bubble_mesh_3 --help)");
  const std::string in_path = o.positional[0];
  if(!o.has("-o") || !ends_with(o.get("-o"), ".mesh"))
    throw Usage_error("adapt: give -o OUT.mesh");
  if(!o.has("--solution"))
    throw Usage_error("adapt: give --solution U.sol (one scalar value per vertex of " + file_name(in_path) + ")");
  if(o.has("--error") == o.has("--target-vertices"))
    throw Usage_error("adapt: give exactly one of --error E and --target-vertices N");
  for(const char* name : {"--interpolate-solution", "--metric-out"})
    if(o.has(name) && !ends_with(o.get(name), ".sol"))
      throw Usage_error(std::string(name) + ": '" + o.get(name) + "' must end in .sol");
  if(o.has("--vtu") && !ends_with(o.get("--vtu"), ".vtu"))
    throw Usage_error("--vtu: '" + o.get("--vtu") + "' must end in .vtu");
  auto positive = [&](const char* name, double fallback) {
    if(!o.has(name))
      return fallback;
    const double v = parse_number(o.get(name), name);
    if(!(v > 0))
      throw Usage_error(std::string(name) + " must be positive");
    return v;
  };
  double gradation = 1.5;
  if(o.has("--gradation")) {
    gradation = o.get("--gradation") == "off" ? 0.0 : parse_number(o.get("--gradation"), "--gradation");
    if(o.get("--gradation") != "off" && !(gradation > 1 && std::isfinite(gradation)))
      throw Usage_error("--gradation must be a number above 1 (e.g. 1.5) or 'off'");
  }
  const bool quiet = o.has("--quiet");
  const std::function<void(const std::string&)> progress = progress_printer(quiet);

  const Indexed_tet_mesh_3 input = BIO::read_medit(in_path);
  const std::vector<double> solution = BIO::read_scalar_sol(o.get("--solution"), input.points.size());
  progress("read " + file_name(in_path) + ": " + std::to_string(input.points.size()) + " vertices, " +
           std::to_string(input.tets.size()) + " tets; solution " + file_name(o.get("--solution")));
  std::array<double, 3> lo{{1e300, 1e300, 1e300}}, hi{{-1e300, -1e300, -1e300}};
  for(const auto& p : input.points)
    for(int k = 0; k < 3; ++k) {
      lo[std::size_t(k)] = std::min(lo[std::size_t(k)], p[std::size_t(k)]);
      hi[std::size_t(k)] = std::max(hi[std::size_t(k)], p[std::size_t(k)]);
    }
  const double diagonal = std::sqrt(CGAL::square(hi[0] - lo[0]) + CGAL::square(hi[1] - lo[1]) + CGAL::square(hi[2] - lo[2]));
  const double hmin = positive("--hmin", diagonal * 1e-4), hmax = positive("--hmax", diagonal / 10);
  const double surface_distance = parse_surface_distance(o, -1.0); // default auto
  const double ratio = positive("--max-ratio", 1000);
  const double norm = positive("--norm", 2);
  const double angle = o.has("--feature-angle") ? parse_number(o.get("--feature-angle"), "--feature-angle") : 60.0;
  if(!(angle >= 0 && angle <= 180))
    throw Usage_error("--feature-angle must be between 0 and 180 degrees");
  const double time_limit = positive("--time-limit", std::numeric_limits<double>::infinity());
  const double max_nodes = positive("--max-nodes", BM::default_maximum_number_of_nodes);
  const unsigned seed = o.has("--seed") ? unsigned(parse_count(o.get("--seed"), "--seed")) : 0u;
  const int threads = o.has("--threads") ? parse_count(o.get("--threads"), "--threads") : 0;

  const auto bounds =
      BM::parameters::minimum_size(hmin).maximum_size(hmax).maximum_anisotropy(ratio).error_norm(norm);
  const std::string name = "Hessian metric of " + file_name(o.get("--solution"));

  BM::Meshing_report meshing;
  Indexed_tet_mesh_3 mesh;
  BM::Quality_report quality;
  auto say_metric = [&](double estimate, const std::string& graded) {
    std::ostringstream m;
    m << "metric: Hessian of the solution, "
      << (o.has("--error") ? "error " + o.get("--error") : "target " + o.get("--target-vertices") + " vertices")
      << ", sizes in [" << hmin << ", " << hmax << "], ratio <= " << ratio << graded << "; about "
      << std::lround(estimate) << " vertices";
    progress(m.str());
  };
  auto run = [&](const auto& field) {
    mesh = BM::remesh_anisotropic_3(
        input, field,
        meshing_parameters(seed, threads, max_nodes, meshing, !o.has("--no-improve"), time_limit, progress)
            .feature_angle(angle)
            .surface_distance(surface_distance));
    quality = BM::compute_quality_report(mesh, field);
    if(o.has("--metric-out")) {
      std::vector<Metric_3> metrics;
      for(const auto& p : input.points)
        metrics.push_back(field(K::Point_3(p[0], p[1], p[2])));
      BIO::write_sol(o.get("--metric-out"), metrics);
    }
  };
  auto build_and_run = [&](const auto& np) {
    if(gradation > 0) {
      const auto graded = CGAL::make_graded_hessian_metric_field_3<K>(input, solution, gradation, np, name);
      say_metric(CGAL::Hessian_metric_field_3<K>::estimated_number_of_vertices(input, graded.vertex_metrics()),
                 ", gradation " + std::to_string(gradation).substr(0, 4) + " (" +
                     std::to_string(graded.number_of_clipped_vertices()) + " of " +
                     std::to_string(input.points.size()) + " vertex metrics reduced)");
      run(graded);
    } else {
      const CGAL::Hessian_metric_field_3<K> hessian(input, solution, np, name);
      say_metric(hessian.estimated_number_of_vertices(), ", no gradation");
      run(hessian);
    }
  };
  const int failed = exit_code_of_meshing([&] {
    if(o.has("--error"))
      build_and_run(bounds.interpolation_error(positive("--error", 0)));
    else
      build_and_run(
          bounds.target_number_of_vertices(double(parse_count(o.get("--target-vertices"), "--target-vertices"))));
  });
  if(failed != 0)
    return failed;
  quality.metric_description = "Hessian metric of " + file_name(o.get("--solution"));
  BIO::write_medit(o.get("-o"), mesh);
  progress("wrote " + o.get("-o"));
  if(o.has("--interpolate-solution")) {
    BIO::write_scalar_sol(o.get("--interpolate-solution"), BM::interpolate_vertex_values(input, solution, mesh.points));
    progress("wrote " + o.get("--interpolate-solution"));
  }
  if(o.has("--vtu"))
    BIO::write_vtu(o.get("--vtu"), mesh);
  if(o.has("--report")) {
    std::string json = BM::to_json(quality);
    json.insert(json.rfind("\n}"), ",\n  \"meshing\": " + BM::to_json(meshing));
    BIO::write_text_file(o.get("--report"), json + "\n");
  }
  if(!quiet) {
    BM::print_meshing_summary(std::cout, meshing);
    BM::print_quality_summary(std::cout, quality);
  }
  return 0;
}

} // namespace

int main(int argc, char** argv)
{
  std::signal(SIGINT, on_sigint);
  try {
    if(argc < 2)
      throw Usage_error("missing command (see bubble_mesh_3 --help)");
    const std::string command = argv[1];
    if(command == "--help" || command == "-h" || command == "help") {
      std::cout << usage_text;
      return 0;
    }
    if(command == "--version") {
      std::cout << "bubble_mesh_3 0.1.0\n";
      return 0;
    }
    if(command == "eval")
      return run_eval(argc, argv);
    if(command == "convert")
      return run_convert(argc, argv);
    if(command == "adapt")
      return run_adapt(argc, argv);
    if(!command.empty() && command[0] != '-')
      return run_mesh(argc, argv);
    throw Usage_error("unknown command '" + command + "' (see bubble_mesh_3 --help)");
  } catch(const Invalid_input& e) {
    std::cerr << "bubble_mesh_3: error: " << e.what() << "\n";
    return 2;
  } catch(const CGAL::Bubble_mesh_3::Interrupted& e) {
    std::cerr << "bubble_mesh_3: " << e.what() << " (SIGINT)\n";
    return exit_interrupted;
  } catch(const std::bad_alloc&) {
    std::cerr << "bubble_mesh_3: error: out of memory\n";
    return 3;
  } catch(const std::exception& e) {
    std::cerr << "bubble_mesh_3: internal error: " << e.what() << "\n";
    return 3;
  }
}
