/*!
\ingroup PkgBubbleMesh3Concepts
\cgalConcept

The concept `AnisotropicAdvancingFrontTraits_3` describes the geometric
traits of the anisotropic advancing front: the exact predicates that decide
the combinatorics of the mesh, measured in a Riemannian metric given as a
symmetric positive definite matrix `M` of doubles.

A metric predicate measures in the space where `M` becomes the identity:
points are mapped by any `Q` with `M = Q^T Q` and `det Q > 0`. Models must
decide it from the points and the entries of `M` themselves, never from a
rounded `Q`, so that the answers are exact for the given inputs and
mutually consistent as long as one `M` is used for all the tests of one
decision.

\cgalHasModel `CGAL::Bubble_mesh_3::Anisotropic_advancing_front_traits_3<K>`

\sa `CGAL::Bubble_mesh_3::Metric_3`
*/
class AnisotropicAdvancingFrontTraits_3 {
public:

/// \name Types
/// @{

/// The number type of the coordinates.
typedef unspecified_type FT;

/// The point type.
typedef unspecified_type Point_3;

/// A symmetric positive definite 3x3 matrix stored as doubles: the exact
/// input of the metric predicates. Must be `CGAL::Bubble_mesh_3::Metric_3`.
typedef unspecified_type Metric_3;

/// A predicate object, exact, with the operator
/// `CGAL::Orientation operator()(const Point_3& p, const Point_3& q, const Point_3& r, const Point_3& s)`
/// of `Kernel::Orientation_3`.
typedef unspecified_type Orientation_3;

/// A predicate object, exact, with the operator
/// `CGAL::Oriented_side operator()(const Point_3& p, const Point_3& q, const Point_3& r, const Point_3& s, const Point_3& t, const Metric_3& M)`.
///
/// It returns the side of the oriented M-circumsphere of `p, q, r, s` (the
/// ellipsoid `{x : (x-c)^T M (x-c) = rho^2}` through the four points) on
/// which `t` lies, with the convention of `Kernel::Side_of_oriented_sphere_3`:
/// if `orientation(p, q, r, s) == CGAL::POSITIVE`, `CGAL::ON_POSITIVE_SIDE`
/// means strictly inside, `CGAL::ON_NEGATIVE_SIDE` strictly outside and
/// `CGAL::ON_ORIENTED_BOUNDARY` on the ellipsoid; the result is reversed
/// for a negative orientation. Swapping two of `p, q, r, s` reverses the
/// result; the product with `orientation(p, q, r, s)` is the bounded side.
/// For `M` the identity it is `Kernel::Side_of_oriented_sphere_3`.
typedef unspecified_type Side_of_oriented_metric_sphere_3;

/// A predicate object, exact, with the operator
/// `CGAL::Oriented_side operator()(const Point_3& p, const Point_3& q, const Point_3& r, const Point_3& s, const Point_3& t, const Metric_3& M, std::size_t id_p, std::size_t id_q, std::size_t id_r, std::size_t id_s, std::size_t id_t)`.
///
/// The same test under a symbolic perturbation keyed by the vertex ids:
/// the result of `Side_of_oriented_metric_sphere_3` when that is not
/// `CGAL::ON_ORIENTED_BOUNDARY`; otherwise the sign after raising the lifting
/// `d^T M d` of the point with the `k`-th largest id by `epsilon^k`, for an
/// infinitely small `epsilon > 0` (the largest id is perturbed the most).
/// It never returns `CGAL::ON_ORIENTED_BOUNDARY` when `p, q, r, s` are not
/// coplanar, and permuting the five (point, id) pairs multiplies the result by
/// the sign of the permutation.
///
/// \pre The five ids are distinct, and a point always carries the same id.
typedef unspecified_type Side_of_oriented_metric_sphere_SOS_3;

/// segment and triangle types (`Segment_3(p, q)`, `Triangle_3(p, q, r)`)
typedef unspecified_type Segment_3;
typedef unspecified_type Triangle_3;

/// exact intersection tests `bool operator()(Triangle_3, Triangle_3)` and
/// `bool operator()(Segment_3, Triangle_3)` (closed sets: touching counts),
/// as `Kernel::Do_intersect_3`; the front refuses a tet whose new faces meet
/// the front anywhere but in shared vertices and edges
typedef unspecified_type Do_intersect_3;

/// `CGAL::Orientation operator()(p, q, r, s)` for coplanar points: `POSITIVE`
/// when `r` and `s` lie on the same side of the line `pq`, as
/// `Kernel::Coplanar_orientation_3`
typedef unspecified_type Coplanar_orientation_3;

/// @}

/// \name Operations
/// @{

/// returns an `Orientation_3` object
Orientation_3 orientation_3_object() const;

/// returns a `Side_of_oriented_metric_sphere_3` object
Side_of_oriented_metric_sphere_3 side_of_oriented_metric_sphere_3_object() const;

/// returns a `Side_of_oriented_metric_sphere_SOS_3` object
Side_of_oriented_metric_sphere_SOS_3 side_of_oriented_metric_sphere_SOS_3_object() const;

/// returns a `Do_intersect_3` object
Do_intersect_3 do_intersect_3_object() const;

/// returns a `Coplanar_orientation_3` object
Coplanar_orientation_3 coplanar_orientation_3_object() const;

/// @}

}; /* end AnisotropicAdvancingFrontTraits_3 */
