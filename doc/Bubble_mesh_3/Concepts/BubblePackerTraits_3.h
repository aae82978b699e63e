/*!
\ingroup PkgBubbleMesh3Concepts
\cgalConcept

The physics of `CGAL::Bubble_packer_3`: the inter-bubble force law, the
normalized distance of two anisotropic bubbles (current length over neutral
length), the integrator of the damped dynamics, and the thresholds of adaptive
population control. The packer owns the stages, the neighbour search, the
convergence test and the population-control bookkeeping.

Convention: a bubble is the metric ball of radius 1/2 around its centre, so
two bubbles of equal metric are at rest at metric distance 1.

\cgalHasModel `CGAL::Bubble_packer_traits_3<K>`
*/
class BubblePackerTraits_3 {
public:
  /// \name Types
  /// @{
  typedef unspecified_type Kernel;
  typedef unspecified_type FT;
  typedef unspecified_type Point_3;
  /// `CGAL::Bubble_mesh_3::Metric_3`
  typedef unspecified_type Metric;

  /// Functor: `double operator()(double w) const`, the force of normalized
  /// distance `w` (positive repulsive, negative attractive), and
  /// `double cutoff() const`, the largest `w` with a non-zero force.
  typedef unspecified_type Compute_interbubble_force;

  /// Functor: `double operator()(double a, double b) const`, the normalized
  /// distance `w = l / l0` from the metric lengths `a = |d|_{M_i}` and
  /// `b = |d|_{M_j}` of the segment `d` between the two centres.
  /// Note: the packer's force direction is the gradient of the pair energy
  /// for the default, `w = 2ab / (a + b)` (the harmonic mean); a model that
  /// changes this function gets the magnitude from it but that gradient
  /// direction, which is only consistent for the default.
  typedef unspecified_type Compute_normalized_distance;

  /// Functor: `template <class V> V operator()(const V& previous_displacement,
  /// const V& force) const`, the displacement of one time step of the damped
  /// dynamics. The force is the sum over neighbours of `f(w)` times the unit
  /// direction (in the metric of the bubble it acts on), so it is measured in
  /// metric units.
  typedef unspecified_type Integrate_step;
  /// @}

  /// \name Operations
  /// @{
  Compute_interbubble_force compute_interbubble_force_object() const;
  Compute_normalized_distance compute_normalized_distance_object() const;
  Integrate_step integrate_step_object() const;

  /// the largest displacement of one step, in metric units of the bubble
  double maximum_step() const;
  /// optional (true when absent): whether the force includes the variation of
  /// the bubble's own metric with its position (the exact gradient of the pair
  /// energy, directed along the metric geodesic), or takes the metrics as frozen
  /// (directed along the chord between the centres)
  bool metric_gradient_force() const;
  /// overlap `sum_j max(0, 1 - w_ij)` above which a bubble on an entity of dimension `dim` is deleted
  double overlap_deletion_threshold(int dim) const;
  /// a bubble closer than this normalized distance to another one is deleted
  double minimum_distance_deletion_threshold(int dim) const;
  /// a probe point at normalized distance at least this from every bubble is a gap
  double gap_insertion_threshold(int dim) const;
  /// metric distance of the gap probes from the bubble that probes
  double gap_probe_distance(int dim) const;
  /// population control runs every that many iterations
  int population_control_period() const;
  /// at most that many population-control rounds per stage
  int maximum_population_rounds() const;
  /// at most that fraction of the moving bubbles is inserted, or deleted, per round
  double maximum_change_fraction() const;
  /// a round on a relaxed packing changing at most that fraction of the moving bubbles ends population control
  double population_stability_fraction() const;
  /// @}
};
