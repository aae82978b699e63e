// bench_quality_competitors: the competitors' meshes for the quality comparison
// (benchmark/Bubble_mesh_3/run_quality_comparison.sh, RESULTS_quality.md).
//
//   bench_quality_competitors SURFACE TARGET_VERTICES OUT_PREFIX [--feature-angle DEG] [--size0 H]
//                             [--tolerance F] [--facet-distance D] [--max-runs N] [--only mesh3|tetgen]
//                             [--tetgen-remeshed auto|always]
//       Meshes the closed surface with CGAL Mesh_3 (Polyhedral_mesh_domain_with_features_3,
//       detect_features(DEG), criteria from one size s, facet_distance D or s/10,
//       perturb + exude) and with TetGen
//       (-pq1.414a<maxvol>), s and maxvol found by a few secant/bisection runs so that the
//       vertex count is TARGET_VERTICES within +-F (default 0.1). TetGen keeps every input
//       vertex: when that alone is too many (auto) or always, a second TetGen mesh is made
//       from the surface remeshed isotropically (PMP) at a fitted edge length.
//       Writes OUT_PREFIX_{mesh3,tetgen,tetgen_remeshed}.mesh (MEDIT) and
//       OUT_PREFIX_competitors.json (counts, wall times, every trial). Exit 0 when all
//       reached the band, 1 when one did not (the closest mesh is written anyway), 2 on
//       invalid input or a failed run.
//
//   bench_quality_competitors eval-boundary-layer MESH SURFACE HN,HT,T --report R.json
//       The quality report of `bubble_mesh_3 eval` (same JSON) in the surface-aligned
//       boundary-layer metric, which the CLI's eval does not offer (it needs the surface).
//
// Google Benchmark is linked by the benchmark CMake glob but not used: each mesher
// runs once per trial and the wall time of that one run is what is compared.
#include <CGAL/Bubble_mesh_3/IO/medit.h>
#include <CGAL/Bubble_mesh_3/IO/read_triangle_surface.h>
#include <CGAL/Bubble_mesh_3/IO/write_file_atomically.h>
#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/Quality_report.h>
#include <CGAL/Bubble_mesh_3/analytic_metric_fields.h>
#include <CGAL/Bubble_mesh_3/validity.h>
#include <CGAL/Function_metric_field_3.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polygon_mesh_processing/detect_features.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>
#include <CGAL/boost/graph/copy_face_graph.h>
#include <CGAL/make_mesh_3.h>

#ifdef BUBBLE_MESH_3_HAS_TETGEN
#include <tetgen.h>
#endif

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Surface_mesh<K::Point_3> Surface;
using CGAL::Bubble_mesh_3::Indexed_tet_mesh_3;
namespace BM = CGAL::Bubble_mesh_3;

double seconds_since(std::chrono::steady_clock::time_point t0)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Tets and boundary triangles as produced by a mesher, before clean-up.
struct Raw_mesh {
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<int, 4>> tets;
  std::vector<std::array<int, 3>> boundary;
  std::vector<int> boundary_refs;
};

// Keeps only the points used by tets, makes every tet positively oriented and
// every boundary triangle outward (seen from its tet), so that the file passes
// the same validity checks as ours whatever the mesher's conventions are.
Indexed_tet_mesh_3 to_indexed_mesh(const Raw_mesh& raw)
{
  Indexed_tet_mesh_3 m;
  std::vector<int> new_index(raw.points.size(), -1);
  auto index_of = [&](int v) {
    if(new_index[v] < 0) {
      new_index[v] = static_cast<int>(m.points.size());
      m.points.push_back(raw.points[v]);
    }
    return new_index[v];
  };
  auto point = [&](int v) { return K::Point_3(m.points[v][0], m.points[v][1], m.points[v][2]); };
  // sorted face -> the tet vertex opposite to it
  std::map<std::array<int, 3>, int> opposite;
  for(const std::array<int, 4>& t : raw.tets) {
    std::array<int, 4> c{index_of(t[0]), index_of(t[1]), index_of(t[2]), index_of(t[3])};
    if(CGAL::orientation(point(c[0]), point(c[1]), point(c[2]), point(c[3])) == CGAL::NEGATIVE)
      std::swap(c[2], c[3]);
    m.tets.push_back(c);
    m.tet_refs.push_back(1);
    for(int i = 0; i < 4; ++i) {
      std::array<int, 3> f{c[(i + 1) % 4], c[(i + 2) % 4], c[(i + 3) % 4]};
      std::sort(f.begin(), f.end());
      opposite[f] = c[i];
    }
  }
  for(std::size_t k = 0; k < raw.boundary.size(); ++k) {
    const std::array<int, 3>& b = raw.boundary[k];
    if(new_index[b[0]] < 0 || new_index[b[1]] < 0 || new_index[b[2]] < 0)
      continue; // not a face of any kept tet
    std::array<int, 3> t{new_index[b[0]], new_index[b[1]], new_index[b[2]]};
    std::array<int, 3> key = t;
    std::sort(key.begin(), key.end());
    const auto it = opposite.find(key);
    if(it == opposite.end())
      continue;
    // outward: the tet's own vertex lies on the negative side of the triangle
    if(CGAL::orientation(point(t[0]), point(t[1]), point(t[2]), point(it->second)) == CGAL::POSITIVE)
      std::swap(t[1], t[2]);
    m.triangles.push_back(t);
    m.triangle_refs.push_back(raw.boundary_refs.empty() ? 1 : raw.boundary_refs[k]);
  }
  m.point_refs.assign(m.points.size(), 0);
  return m;
}

// One run of a mesher at one parameter value.
struct Trial {
  double parameter = 0;
  std::size_t vertices = 0;
  std::size_t tets = 0;
  double seconds = 0;
};

struct Fit_result {
  std::vector<Trial> trials;
  std::optional<Indexed_tet_mesh_3> best_mesh;
  Trial best;
  bool in_band = false;
  std::string note;
};

// Finds a parameter p (a length or a volume; the vertex count decreases with it,
// roughly like p^-exponent) whose mesh has `target` vertices within `tolerance`:
// secant steps in log-log space, kept inside the current bracket (geometric
// bisection when they leave it). Keeps the mesh closest to the target.
Fit_result fit_vertex_count(double p0, double exponent, std::size_t target, double tolerance, int max_runs,
                            const std::function<Indexed_tet_mesh_3(double, double&)>& run, const std::string& name)
{
  Fit_result r;
  double lo = 0, hi = 0; // lo: largest p giving too many vertices; hi: smallest p giving too few
  double p = p0;
  for(int k = 0; k < max_runs; ++k) {
    double seconds = 0;
    Indexed_tet_mesh_3 mesh;
    try {
      mesh = run(p, seconds);
    } catch(const std::runtime_error& e) {
      // a failed run (TetGen on a self-intersecting remeshed surface): try a slightly larger parameter
      std::cerr << name << ": parameter " << p << " failed: " << e.what() << "\n";
      r.note += std::string(r.note.empty() ? "" : "; ") + "parameter " + std::to_string(p) + " failed: " + e.what();
      p *= 1.07;
      continue;
    }
    Trial t;
    t.parameter = p;
    t.vertices = mesh.points.size();
    t.tets = mesh.tets.size();
    t.seconds = seconds;
    r.trials.push_back(t);
    std::cerr << name << ": parameter " << p << " -> " << t.vertices << " vertices, " << t.tets << " tets, "
              << seconds << " s\n";
    const double error = std::abs(double(t.vertices) - double(target)) / double(target);
    if(!r.best_mesh || error < std::abs(double(r.best.vertices) - double(target)) / double(target)) {
      r.best = t;
      r.best_mesh = std::move(mesh);
    }
    if(error <= tolerance) {
      r.in_band = true;
      break;
    }
    if(t.vertices > target)
      lo = std::max(lo, p);
    else
      hi = (hi == 0) ? p : std::min(hi, p);
    // local exponent from the last two trials when they differ enough
    double e = exponent;
    if(r.trials.size() >= 2) {
      const Trial& a = r.trials[r.trials.size() - 2];
      if(a.vertices != t.vertices && std::abs(std::log(a.parameter / t.parameter)) > 1e-6) {
        const double measured = -std::log(double(a.vertices) / double(t.vertices)) / std::log(a.parameter / t.parameter);
        if(measured > 0)
          e = std::clamp(measured, 0.25 * exponent, 2 * exponent);
      }
    }
    double next = p * std::pow(double(t.vertices) / double(target), 1 / e);
    if(lo > 0 && hi > 0 && !(next > lo && next < hi))
      next = std::sqrt(lo * hi);
    if(std::abs(next / p - 1) < 1e-9) {
      r.note = "the parameter no longer changes the vertex count";
      break;
    }
    p = next;
  }
  if(!r.in_band)
    r.note += std::string(r.note.empty() ? "" : "; ") + "no run within the band after " +
              std::to_string(r.trials.size()) + " successful runs";
  return r;
}

// ---------------------------------------------------------------- CGAL Mesh_3
typedef CGAL::Polyhedral_mesh_domain_with_features_3<K> Domain;
typedef CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type Mesh3_tr;
typedef CGAL::Mesh_complex_3_in_triangulation_3<Mesh3_tr, Domain::Corner_index, Domain::Curve_index> Mesh3_c3t3;
typedef CGAL::Mesh_criteria_3<Mesh3_tr> Mesh3_criteria;

// Mesh_3's output restricted to the complex: cells in the complex, their
// vertices (so the count is comparable to ours), facets in the complex.
Raw_mesh raw_from_c3t3(const Mesh3_c3t3& c3t3)
{
  Raw_mesh raw;
  std::map<Mesh3_tr::Vertex_handle, int> index;
  auto index_of = [&](Mesh3_tr::Vertex_handle v) {
    auto it = index.find(v);
    if(it != index.end())
      return it->second;
    const auto p = c3t3.triangulation().point(v).point();
    raw.points.push_back({CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())});
    const int i = static_cast<int>(raw.points.size()) - 1;
    index.emplace(v, i);
    return i;
  };
  for(auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c)
    raw.tets.push_back({index_of(c->vertex(0)), index_of(c->vertex(1)), index_of(c->vertex(2)),
                        index_of(c->vertex(3))});
  for(auto f = c3t3.facets_in_complex_begin(); f != c3t3.facets_in_complex_end(); ++f) {
    std::array<int, 3> t;
    for(int j = 0, k = 0; j < 4; ++j)
      if(j != f->second)
        t[k++] = index_of(f->first->vertex(j));
    raw.boundary.push_back(t);
    raw.boundary_refs.push_back(1);
  }
  return raw;
}

// Criteria from one size s: Mesh_3's usual settings (facet angle 25 degrees,
// radius-edge ratio 3) with every size bound s and the approximation bound
// `facet_distance` (0: s/10).
Indexed_tet_mesh_3 run_mesh3(const Domain& domain, double s, double facet_distance, double& seconds)
{
  Mesh3_criteria criteria(CGAL::parameters::edge_size = s, CGAL::parameters::facet_angle = 25,
                          CGAL::parameters::facet_size = s,
                          CGAL::parameters::facet_distance = facet_distance > 0 ? facet_distance : 0.1 * s,
                          CGAL::parameters::cell_radius_edge_ratio = 3, CGAL::parameters::cell_size = s);
  const auto t0 = std::chrono::steady_clock::now();
  // Mesh_3's defaults, spelled out: sliver perturbation then exudation.
  Mesh3_c3t3 c3t3 = CGAL::make_mesh_3<Mesh3_c3t3>(domain, criteria, CGAL::parameters::perturb(),
                                                  CGAL::parameters::exude());
  seconds = seconds_since(t0);
  return to_indexed_mesh(raw_from_c3t3(c3t3));
}

// -------------------------------------------------------------------- TetGen
#ifdef BUBBLE_MESH_3_HAS_TETGEN
Indexed_tet_mesh_3 run_tetgen(const Surface& surface, double max_volume, double& seconds)
{
  tetgenio in, out;
  in.firstnumber = 0;
  std::map<Surface::Vertex_index, int> index;
  in.numberofpoints = static_cast<int>(surface.number_of_vertices());
  in.pointlist = new REAL[3 * in.numberofpoints];
  int n = 0;
  for(Surface::Vertex_index v : surface.vertices()) {
    const K::Point_3& p = surface.point(v);
    in.pointlist[3 * n] = p.x();
    in.pointlist[3 * n + 1] = p.y();
    in.pointlist[3 * n + 2] = p.z();
    index[v] = n++;
  }
  in.numberoffacets = static_cast<int>(surface.number_of_faces());
  in.facetlist = new tetgenio::facet[in.numberoffacets];
  int k = 0;
  for(Surface::Face_index f : surface.faces()) {
    tetgenio::facet& facet = in.facetlist[k++];
    tetgenio::init(&facet);
    facet.numberofpolygons = 1;
    facet.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&facet.polygonlist[0]);
    facet.polygonlist[0].numberofvertices = 3;
    facet.polygonlist[0].vertexlist = new int[3];
    int j = 0;
    for(Surface::Vertex_index v : CGAL::vertices_around_face(surface.halfedge(f), surface))
      facet.polygonlist[0].vertexlist[j++] = index[v];
  }
  std::ostringstream switches;
  switches << "pq1.414";
  if(max_volume > 0)
    switches << "a" << max_volume;
  switches << "zQ";
  std::string s = switches.str();
  const auto t0 = std::chrono::steady_clock::now();
  try {
    tetrahedralize(&s[0], &in, &out);
  } catch(int code) { // TetGen reports errors by throwing its exit code (3: self-intersecting input)
    throw std::runtime_error("TetGen -" + s + " stopped with error code " + std::to_string(code));
  }
  seconds = seconds_since(t0);

  Raw_mesh raw;
  for(int i = 0; i < out.numberofpoints; ++i)
    raw.points.push_back({out.pointlist[3 * i], out.pointlist[3 * i + 1], out.pointlist[3 * i + 2]});
  for(int i = 0; i < out.numberoftetrahedra; ++i) {
    const int* t = out.tetrahedronlist + i * out.numberofcorners;
    raw.tets.push_back({t[0], t[1], t[2], t[3]});
  }
  for(int i = 0; i < out.numberoftrifaces; ++i) {
    const int* t = out.trifacelist + 3 * i;
    raw.boundary.push_back({t[0], t[1], t[2]});
  }
  return to_indexed_mesh(raw);
}

// The input surface remeshed isotropically at edge length `l`, edges sharper
// than `angle` kept as (splittable, collapsible) constraints, so that TetGen,
// which keeps every input vertex, can reach coarse vertex counts.
Surface remesh_surface(const Surface& input, double l, double angle)
{
  namespace PMP = CGAL::Polygon_mesh_processing;
  Surface m = input;
  auto sharp = m.add_property_map<Surface::Edge_index, bool>("e:sharp", false).first;
  PMP::detect_sharp_edges(m, angle, sharp);
  PMP::isotropic_remeshing(faces(m), l, m, PMP::parameters::number_of_iterations(5).edge_is_constrained_map(sharp));
  m.collect_garbage();
  // TetGen may crash instead of failing on a self-intersecting surface (thin
  // parts of the elephant, remeshed coarsely, intersect themselves)
  if(PMP::does_self_intersect(m))
    throw std::runtime_error("the surface remeshed at edge " + std::to_string(l) + " intersects itself");
  return m;
}
#endif

// ----------------------------------------------------------------- the program
std::string trials_json(const Fit_result& r)
{
  std::ostringstream j;
  j << "[";
  for(std::size_t i = 0; i < r.trials.size(); ++i) {
    const Trial& t = r.trials[i];
    j << (i ? ", " : "") << "{\"parameter\": " << t.parameter << ", \"vertices\": " << t.vertices
      << ", \"tets\": " << t.tets << ", \"seconds\": " << t.seconds << "}";
  }
  j << "]";
  return j.str();
}

std::string result_json(const std::string& mesher, const std::string& parameter_name, const Fit_result& r,
                         const std::string& path, double setup_seconds)
{
  std::ostringstream j;
  j.precision(10);
  j << "  \"" << mesher << "\": {\"mesh\": \"" << path << "\", \"parameter_name\": \"" << parameter_name
    << "\", \"parameter\": " << r.best.parameter << ", \"vertices\": " << r.best.vertices
    << ", \"tets\": " << r.best.tets << ", \"seconds\": " << r.best.seconds
    << ", \"setup_seconds\": " << setup_seconds << ", \"in_band\": " << (r.in_band ? "true" : "false")
    << ", \"note\": \"" << r.note << "\", \"trials\": " << trials_json(r) << "}";
  return j.str();
}

double parse_double(const std::string& s, const std::string& what)
{
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if(s.empty() || end != s.c_str() + s.size() || !std::isfinite(v))
    throw BM::Invalid_input(what + ": '" + s + "' is not a number");
  return v;
}

int run_eval_boundary_layer(int argc, char** argv)
{
  if(argc != 7 || std::string(argv[5]) != "--report")
    throw BM::Invalid_input("usage: eval-boundary-layer MESH SURFACE HN,HT,T --report R.json");
  const std::string mesh_path = argv[2];
  std::vector<double> a;
  std::stringstream ss(argv[4]);
  for(std::string item; std::getline(ss, item, ',');)
    a.push_back(parse_double(item, "HN,HT,T"));
  if(a.size() != 3)
    throw BM::Invalid_input("HN,HT,T: need three numbers");
  const Surface surface = BM::IO::read_triangle_surface<K>(argv[3]);
  const BM::Boundary_layer_metric<K> metric(surface, a[0], a[1], a[2]);
  const auto field = CGAL::make_function_metric_field_3<K>([&metric](const K::Point_3& p) { return metric(p); });
  const Indexed_tet_mesh_3 mesh = BM::IO::read_medit(mesh_path);
  BM::Quality_report report = BM::compute_quality_report(mesh, field);
  report.metric_description = std::string("boundary layer ") + argv[4];
  // the options of `bubble_mesh_3 eval`, so that both evaluations agree
  BM::Validity_options options;
  options.allow_unused_vertices = true;
  options.allow_duplicate_triangles = true;
  const BM::Validity_report validity = BM::check_validity(mesh, options);
  std::string json = BM::to_json(report);
  json.insert(json.rfind("\n}"), ",\n  \"validity\": " + BM::to_json(validity));
  BM::IO::write_text_file(argv[6], json + "\n");
  BM::print_quality_summary(std::cout, report);
  BM::print_validity_summary(std::cout, validity);
  return 0;
}

int run_competitors(int argc, char** argv)
{
  if(argc < 4)
    throw BM::Invalid_input("usage: bench_quality_competitors SURFACE TARGET_VERTICES OUT_PREFIX [--feature-angle DEG] "
                            "[--size0 H] [--tolerance F] [--facet-distance D] [--max-runs N] [--only mesh3|tetgen] "
                            "[--tetgen-remeshed auto|always]");
  const std::string surface_path = argv[1];
  const double target_d = parse_double(argv[2], "TARGET_VERTICES");
  if(!(target_d >= 10))
    throw BM::Invalid_input("TARGET_VERTICES must be at least 10");
  const std::size_t target = static_cast<std::size_t>(target_d);
  const std::string prefix = argv[3];
  double angle = 60, size0 = 0, tolerance = 0.1, facet_distance = 0;
  int max_runs = 8;
  bool remesh_always = false;
  std::string only;
  for(int i = 4; i < argc; i += 2) {
    const std::string o = argv[i];
    if(i + 1 >= argc)
      throw BM::Invalid_input(o + " needs a value");
    const std::string v = argv[i + 1];
    if(o == "--feature-angle")
      angle = parse_double(v, o);
    else if(o == "--size0")
      size0 = parse_double(v, o);
    else if(o == "--tolerance")
      tolerance = parse_double(v, o);
    else if(o == "--facet-distance")
      facet_distance = parse_double(v, o);
    else if(o == "--max-runs")
      max_runs = static_cast<int>(parse_double(v, o));
    else if(o == "--tetgen-remeshed" && (v == "auto" || v == "always"))
      remesh_always = (v == "always");
    else if(o == "--only" && (v == "mesh3" || v == "tetgen"))
      only = v;
    else
      throw BM::Invalid_input("unknown option " + o + " " + v);
  }

  const Surface surface = BM::IO::read_triangle_surface<K>(surface_path);
  const CGAL::Bbox_3 bb = CGAL::Polygon_mesh_processing::bbox(surface);
  const double diagonal = std::sqrt(CGAL::square(bb.xmax() - bb.xmin()) + CGAL::square(bb.ymax() - bb.ymin()) +
                                    CGAL::square(bb.zmax() - bb.zmin()));
  double volume = 0; // enclosed volume (divergence theorem), for TetGen's first max volume
  for(Surface::Face_index f : surface.faces()) {
    std::array<K::Point_3, 3> p;
    int j = 0;
    for(Surface::Vertex_index v : CGAL::vertices_around_face(surface.halfedge(f), surface))
      p[j++] = surface.point(v);
    volume += CGAL::to_double(CGAL::determinant(p[0] - CGAL::ORIGIN, p[1] - CGAL::ORIGIN, p[2] - CGAL::ORIGIN)) / 6;
  }
  volume = std::abs(volume);
  std::vector<std::string> parts;
  int status = 0;

  if(only.empty() || only == "mesh3") {
    const auto t0 = std::chrono::steady_clock::now();
    Domain::Polyhedron polyhedron;
    CGAL::copy_face_graph(surface, polyhedron);
    Domain domain(polyhedron);
    domain.detect_features(angle);
    const double setup = seconds_since(t0);
    // an FCC packing of edge s has sqrt(2)/s^3 vertices per unit volume
    const double s0 = size0 > 0 ? size0 : std::cbrt(std::sqrt(2.0) * volume / double(target));
    Fit_result r = fit_vertex_count(
        s0, 3, target, tolerance, max_runs,
        [&](double s, double& seconds) { return run_mesh3(domain, s, facet_distance, seconds); }, "Mesh_3");
    const std::string path = prefix + "_mesh3.mesh";
    if(r.best_mesh)
      BM::IO::write_medit(path, *r.best_mesh);
    parts.push_back(result_json("mesh3", "size", r, path, setup));
    if(!r.in_band)
      status = 1;
  }
#ifdef BUBBLE_MESH_3_HAS_TETGEN
  if(only.empty() || only == "tetgen") {
    // Without a volume bound TetGen gives its fewest vertices (it keeps every
    // input vertex); if that is already too many, no -a can help.
    double seconds = 0;
    Indexed_tet_mesh_3 coarsest = run_tetgen(surface, 0, seconds);
    std::cerr << "TetGen: no volume bound -> " << coarsest.points.size() << " vertices\n";
    Fit_result r;
    const std::size_t coarsest_vertices = coarsest.points.size();
    if(double(coarsest_vertices) >= (1 - tolerance) * double(target)) {
      r.best.parameter = 0;
      r.best.vertices = coarsest.points.size();
      r.best.tets = coarsest.tets.size();
      r.best.seconds = seconds;
      r.trials.push_back(r.best);
      r.in_band = double(coarsest.points.size()) <= (1 + tolerance) * double(target);
      r.note = r.in_band ? "no volume bound needed"
                         : "TetGen keeps all input surface vertices: fewest vertices " +
                               std::to_string(coarsest.points.size());
      r.best_mesh = std::move(coarsest);
    } else {
      // a volume bound near twice the mean tet volume of a mesh with `target` vertices (about 6 tets each)
      const double a0 = 2 * volume / (6 * double(target));
      r = fit_vertex_count(
          a0, 1, target, tolerance, max_runs,
          [&](double a, double& s) { return run_tetgen(surface, a, s); }, "TetGen");
    }
    const std::string path = prefix + "_tetgen.mesh";
    if(r.best_mesh)
      BM::IO::write_medit(path, *r.best_mesh);
    parts.push_back(result_json("tetgen", "max_volume", r, path, 0));
    if(!r.in_band)
      status = 1;
    if(double(coarsest_vertices) > (1 + tolerance) * double(target) || remesh_always) {
      // TetGen keeps every input vertex and refines skinny input triangles, so
      // on a dense surface it cannot come down to the target. Second variant:
      // the surface first remeshed isotropically at edge L (sharp edges kept as
      // constraints), then -pq1.414 with the max volume of two regular tets of
      // edge L; L fitted to the vertex count.
      double remesh_seconds = 0;
      const double l0 = size0 > 0 ? size0 : std::cbrt(std::sqrt(2.0) * volume / double(target));
      Fit_result rr = fit_vertex_count(
          l0, 3, target, tolerance, max_runs,
          [&](double l, double& s) {
            const auto t0 = std::chrono::steady_clock::now();
            const Surface remeshed = remesh_surface(surface, l, angle);
            remesh_seconds = seconds_since(t0);
            return run_tetgen(remeshed, 2 * l * l * l / (6 * std::sqrt(2.0)), s);
          },
          "TetGen on remeshed surface");
      const std::string rpath = prefix + "_tetgen_remeshed.mesh";
      if(rr.best_mesh)
        BM::IO::write_medit(rpath, *rr.best_mesh);
      parts.push_back(result_json("tetgen_remeshed", "surface_edge_length", rr, rpath, remesh_seconds));
      if(!rr.in_band)
        status = 1;
    }
  }
#else
  if(only == "tetgen")
    throw BM::Invalid_input("built without TetGen");
#endif
  std::ostringstream json;
  json << "{\n  \"surface\": \"" << surface_path << "\", \"target_vertices\": " << target
       << ", \"tolerance\": " << tolerance << ", \"feature_angle\": " << angle << ", \"bbox_diagonal\": " << diagonal
       << ", \"volume\": " << volume;
  for(const std::string& p : parts)
    json << ",\n" << p;
  json << "\n}\n";
  BM::IO::write_text_file(prefix + "_competitors.json", json.str());
  std::cout << json.str();
  return status;
}

} // namespace

int main(int argc, char** argv)
{
  try {
    if(argc >= 2 && std::string(argv[1]) == "eval-boundary-layer")
      return run_eval_boundary_layer(argc, argv);
    return run_competitors(argc, argv);
  } catch(const std::exception& e) {
    std::cerr << "bench_quality_competitors: " << e.what() << "\n";
    return 2;
  }
}
