/*!
\ingroup PkgBubbleMesh3Concepts
\cgalConcept

A Riemannian metric field: a symmetric positive definite 3x3 matrix `M(p)`
at every point `p` of space.

The metric length of a vector `v` at `p` is `sqrt(v^T M(p) v)`. The package
aims at elements whose edges have metric length 1: the unit "bubble" at `p`
is the ellipsoid `{x : (x-p)^T M(p) (x-p) <= 1/4}` (metric radius 1/2), so
that two touching bubbles have their centres at metric distance 1. With
`M = R diag(1/h_u^2, 1/h_v^2, 1/h_w^2) R^T` the element sizes along the
principal directions (columns of `R`) are `h_u, h_v, h_w`.

Requirements on models:
- `operator()` is `const` and thread-safe: the packer evaluates the field
  concurrently from several threads.
- Every returned value is a valid `Bubble_mesh_3::Metric_3` (finite,
  symmetric, positive definite, eigenvalue ratio at most
  `Metric_3::maximum_eigenvalue_ratio()`). Models validate their input and
  throw `Bubble_mesh_3::Invalid_metric`, naming where (file and vertex, or
  point), instead of returning an invalid value.
- The field should be defined on the whole bounding box of the domain, not
  only inside it (the packer probes points slightly outside).

\cgalHasModel `CGAL::Constant_metric_field_3<K>`
\cgalHasModel `CGAL::Function_metric_field_3<K,F>`
\cgalHasModel `CGAL::Interpolated_metric_field_3<K>`

\sa `MeshDomainField_3` (the isotropic sizing-field concept of Mesh_3)
*/
class MetricField_3 {
public:
  /// \name Types
  /// @{
  /// a model of `Kernel`
  typedef unspecified_type Kernel;
  /// `Kernel::FT`
  typedef unspecified_type FT;
  /// `Kernel::Point_3`
  typedef unspecified_type Point_3;
  /// must be `CGAL::Bubble_mesh_3::Metric_3`
  typedef unspecified_type Metric;
  /// @}

  /// \name Operations
  /// @{
  /// the metric at `p`; may return `Metric` or `const Metric&`
  Metric operator()(const Point_3& p) const;
  /// @}
};
