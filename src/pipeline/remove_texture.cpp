#include "detexture/pipeline/remove_texture.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <utility>

#include "detexture/geometry/estimate_normals.h"
#include "detexture/geometry/orient_normals.h"
#include "detexture/geometry/spatial_order.h"

namespace detexture {

Length parse_length(const std::string& text) {
  if (text == "auto") return {1.5, Length::Unit::Texture};
  std::string number = text;
  Length::Unit unit = Length::Unit::Absolute;
  if (!number.empty() && (number.back() == 't' || number.back() == 'T')) {
    unit = Length::Unit::Texture;
    number.pop_back();
  } else if (!number.empty() && (number.back() == 'd' || number.back() == 'D')) {
    unit = Length::Unit::Diagonal;
    number.pop_back();
  } else if (!number.empty() && (number.back() == 'r' || number.back() == 'R')) {
    unit = Length::Unit::Radius;
    number.pop_back();
  }
  char* end = nullptr;
  const double value = number.empty() ? 0.0 : std::strtod(number.c_str(), &end);
  if (number.empty() || end != number.c_str() + number.size() || !std::isfinite(value))
    throw std::invalid_argument("'" + text +
                                "' is not a length: give a number in the cloud's units, a "
                                "fraction of the bounding-box diagonal such as 0.02d, or a "
                                "multiple of the radius r such as 0.5r (for r itself: 'auto', or "
                                "a multiple of the estimated texture radius such as 1.5t)");
  if (!(value > 0.0)) throw std::invalid_argument("length '" + text + "' must be positive");
  return {value, unit};
}

std::string to_string(const Length& length) {
  const char* suffix = length.unit == Length::Unit::Diagonal  ? "d"
                       : length.unit == Length::Unit::Radius  ? "r"
                       : length.unit == Length::Unit::Texture ? "t"
                                                              : "";
  return number_text(length.value) + suffix;
}

void validate(const RemoveTextureParams& p) {
  for (const auto& [name, len] : {std::pair<const char*, Length>{"radius r", p.radius},
                                  {"lambda", p.lambda},
                                  {"sigma_s", p.sigma_s},
                                  {"sigma_p", p.sigma_p},
                                  {"solve radius", p.solve_radius},
                                  {"normal fit sigma", p.fit_sigma},
                                  {"least surface radius", p.min_surface_radius}})
    if (!(len.value > 0.0) || !std::isfinite(len.value))
      throw std::invalid_argument(std::string(name) + " must be a positive length, got " +
                                  to_string(len));
  if (p.radius.unit == Length::Unit::Radius)
    throw std::invalid_argument(
        "the radius r cannot be given in units of itself; use auto, 0.02d or "
        "a length in the cloud's units");
  for (const auto& [name, len] : {std::pair<const char*, Length>{"lambda", p.lambda},
                                  {"sigma_s", p.sigma_s},
                                  {"sigma_p", p.sigma_p},
                                  {"solve radius", p.solve_radius},
                                  {"normal fit sigma", p.fit_sigma},
                                  {"fallback radius", p.fallback_radius}})
    if (len.unit == Length::Unit::Texture)
      throw std::invalid_argument(std::string(name) +
                                  " cannot be a multiple of the texture radius; only r can (give "
                                  "it in units of r, such as 0.5r)");
  if (p.fallback_radius.unit == Length::Unit::Radius || !(p.fallback_radius.value > 0.0))
    throw std::invalid_argument(
        "the fallback radius must be a positive length in the cloud's "
        "units or of the diagonal");
  if (!(p.fallback_neighbors >= 3.0) || !std::isfinite(p.fallback_neighbors))
    throw std::invalid_argument("the fallback radius needs at least 3 neighbors");
  if (!(p.max_neighbor_share > 0.0) || !(p.max_mean_neighbors > 0.0) ||
      !(p.min_mean_neighbors >= 0.0))
    throw std::invalid_argument("the neighborhood size limits must be positive");
  if (p.radius.unit == Length::Unit::Texture) validate(p.scale);
  if (p.max_neighbors < 0) throw std::invalid_argument("the neighbor cap cannot be negative");
  if (p.max_neighbors > 0 && p.max_neighbors < 3)
    throw std::invalid_argument("a neighbor cap below 3 leaves no plane to fit; use 0 or >= 3");
  if (!(p.move_limit >= 0.0) || !std::isfinite(p.move_limit))
    throw std::invalid_argument("the move limit must be >= 0 (0 for none), got " +
                                number_text(p.move_limit));
  if (!(p.anchor_height >= 0.0) || !std::isfinite(p.anchor_height))
    throw std::invalid_argument("the anchor height must be >= 0 (a multiple of lambda), got " +
                                number_text(p.anchor_height));
  if (!(p.anchor_angle >= 0.0) || !std::isfinite(p.anchor_angle))
    throw std::invalid_argument("the anchor angle must be >= 0 degrees (0 for none), got " +
                                number_text(p.anchor_angle));
  if (!(p.wave_share_low >= 0.0 && p.wave_share_low <= 1.0) ||
      !(p.wave_share_high >= 0.0 && p.wave_share_high <= 1.0))
    throw std::invalid_argument(
        "the shares of the waves' second pass (--wave-share-low, --wave-share-high) must be in "
        "[0, 1], got " +
        number_text(p.wave_share_low) + " and " + number_text(p.wave_share_high));
  if (!(p.wave_rest_anchor > 0.0 && p.wave_rest_anchor <= 1.0))
    throw std::invalid_argument("--wave-rest-anchor must be in (0, 1], got " +
                                number_text(p.wave_rest_anchor));
  if (!(p.wave_ceiling >= 0.0) || !std::isfinite(p.wave_ceiling))
    throw std::invalid_argument("--wave-ceiling must be >= 0, got " + number_text(p.wave_ceiling));
  if (p.wave_share_low < 1.0 && !(p.wave_share_low < p.wave_share_high))
    throw std::invalid_argument("the waves' second pass needs --wave-share-low (" +
                                number_text(p.wave_share_low) + ") below --wave-share-high (" +
                                number_text(p.wave_share_high) +
                                "); --wave-share-low 1 turns it off");
  if (!(p.blend_share_low >= 0.0 && p.blend_share_low <= 1.0) ||
      !(p.blend_share_high >= 0.0 && p.blend_share_high <= 1.0))
    throw std::invalid_argument(
        "the shares of the blend's gate (--blend-share-low, --blend-share-high) must be in "
        "[0, 1], got " +
        number_text(p.blend_share_low) + " and " + number_text(p.blend_share_high));
  if (p.blend_share_high > 0.0 && !(p.blend_share_low < p.blend_share_high))
    throw std::invalid_argument("the blend's gate needs --blend-share-low (" +
                                number_text(p.blend_share_low) + ") below --blend-share-high (" +
                                number_text(p.blend_share_high) +
                                "); --blend-share-high 0 blends on every cloud");
  if (p.normal_neighbors < 3)
    throw std::invalid_argument("normal estimation needs at least 3 neighbors");
  if (p.threads < 0)
    throw std::invalid_argument("the thread count must be 0 (all cores) or positive, got " +
                                std::to_string(p.threads));
  // The stage validators check everything else; lengths are filled in with a
  // placeholder so they do not trip on the unresolved values.
  DetectTextureParams t = p.texture;
  t.lambda = 1.0;
  validate(t);
  FilterNormalsRollingParams r = p.rolling;
  r.sigma_s = 1.0;
  validate(r);
  validate(p.sheets);
  validate(p.orient);
  validate(p.surface_split);
  ShrinkToThinPartsParams thin = p.thin_parts;
  thin.radius = 1.0;
  validate(thin);
  LimitNeighborhoodsToMeshParams paths = p.mesh_paths;
  paths.radius = 1.0;
  validate(paths);
  UpdatePositionsParams u = p.update;
  u.sigma_p = 1.0;
  u.solve_radius = 1.0;
  validate(u);
  FitNormalsToPositionsParams fit = p.output_normals;
  fit.sigma = 1.0;
  fit.radius = 1.0;
  validate(fit);
  KeepInputNormalsParams keep = p.keep_input;
  keep.radius = 1.0;
  keep.lambda = 1.0;
  validate(keep);
  validate(p.counter_moves);
  LimitTipMovesParams tips = p.tips;
  tips.radius = 1.0;
  tips.lambda = 1.0;
  validate(tips);
  LimitSinkMovesParams sinks = p.sinks;
  sinks.radius = 1.0;
  sinks.lambda = 1.0;
  validate(sinks);
  LowerRaisedCellsParams cells = p.raised_cells;
  cells.min_lean = p.counter_moves.engraved_min_lean;
  cells.min_share = p.counter_moves.engraved_share;
  cells.radius = 1.0;
  validate(cells);
}

RadiusChoice choose_radius(const RemoveTextureParams& params, double diagonal,
                           const TextureScaleEstimate& scale) {
  RadiusChoice c;
  if (params.radius.unit != Length::Unit::Texture) {
    c.radius = params.radius.resolve(diagonal, 0.0);
    c.choice = "given";
    c.reason = "given as " + to_string(params.radius);
  } else if (scale.texture_found) {
    c.radius = params.radius.value * scale.texture_radius;
    c.choice = "texture";
    c.reason = number_text(params.radius.value) + " × texture radius";
    // Not across the body's own thin parts (estimate_texture_scale.h, step 5),
    // nor below the radius holding fallback_neighbors.
    const double floor = scale.spacing * std::sqrt(params.fallback_neighbors / M_PI);
    if (scale.thin_radius > 0.0 && c.radius > scale.thin_radius && c.radius > floor) {
      c.radius = std::max(scale.thin_radius, floor);
      char within[32];
      std::snprintf(within, sizeof within, "%.3g", scale.thin_radius);
      c.reason += ", capped at the thickness of thin parts: " +
                  number_text(std::round(100.0 * params.scale.thin_share)) +
                  "% of the surface reaches the back of a thin part within " + within;
    }
  } else {
    const double base = params.fallback_radius.resolve(diagonal, 0.0);
    const double dense = scale.spacing * std::sqrt(params.fallback_neighbors / M_PI);
    c.radius = std::max(base, dense);
    c.choice = "fallback";
    c.reason = "no texture: fallback " +
               (dense > base ? "radius holding about " + number_text(params.fallback_neighbors) +
                                   " neighbors, more than " + to_string(params.fallback_radius)
                             : to_string(params.fallback_radius));
  }
  return c;
}

namespace {

class StageClock {
 public:
  StageClock(const PipelineObserver& observer, RemoveTextureReport& report, std::string stage)
      : observer_(observer),
        report_(report),
        stage_(std::move(stage)),
        start_(std::chrono::steady_clock::now()) {
    if (observer_.begin) observer_.begin(stage_);
  }
  ProgressFn progress() const {
    if (!observer_.progress) return {};
    return [this](double f) { observer_.progress(stage_, f); };
  }
  ~StageClock() {
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    report_.timings.push_back({stage_, s});
    if (observer_.end) observer_.end(stage_, s);
  }

 private:
  const PipelineObserver& observer_;
  RemoveTextureReport& report_;
  std::string stage_;
  std::chrono::steady_clock::time_point start_;
};

void warn(const PipelineObserver& observer, const std::string& message) {
  if (observer.warning) observer.warning(message);
}

}  // namespace

namespace {

// The exact input normals the update fits (RemoveTextureParams::
// update_input_normals): those keep_input_normals would take were nothing to
// move, by its exactness, still and facet tests at `kp` (not the move ramp,
// which would take every normal, nor the reach, which reads output normals
// the update has not made yet). They replace the rows of `normals`; the rows
// they replace are listed with their old values in `replaced`, so that the
// caller can put them back.
void take_exact_input_normals(const Positions& P, const Normals& input,
                              const std::vector<std::uint8_t>& is_texture, const Neighborhoods& R,
                              KeepInputNormalsParams kp, Normals& normals,
                              std::vector<std::pair<std::uint32_t, Eigen::RowVector3d>>& replaced) {
  kp.high = 0.0;
  kp.reached_angle_deg = 0.0;
  const KeepInputNormalsResult k = keep_input_normals(P, P, input, normals, is_texture, R, kp);
  replaced.clear();
  for (std::size_t i = 0; i < static_cast<std::size_t>(normals.rows()); ++i) {
    if (k.normals.row(i) == normals.row(i)) continue;
    replaced.emplace_back(static_cast<std::uint32_t>(i), normals.row(i));
    normals.row(i) = k.normals.row(i);
  }
}

// Where a share of flagged points lies between low (0) and high (1), clamped:
// the gates of the waves' second pass and of the blend's open window.
double share_ramp(double share, double low, double high) {
  return std::clamp((share - low) / (high - low), 0.0, 1.0);
}

// The memory guard: refuse before building neighborhoods that would not fit.
void check_memory(const Positions& P, const RemoveTextureParams& params, RemoveTextureReport& rep) {
  const std::uint64_t limit =
      params.memory_limit != 0 ? params.memory_limit : default_memory_limit();
  if (limit == 0 || limit == std::numeric_limits<std::uint64_t>::max()) return;
  constexpr std::size_t kSamples = 256;
  const NeighborhoodsMemoryEstimate e = estimate_neighborhoods_memory(
      P, {rep.radius, params.max_neighbors}, kSamples, static_cast<double>(limit));
  rep.estimated_bytes = e.bytes;
  if (e.bytes <= static_cast<double>(limit)) return;
  const bool early = e.sampled < std::min<std::size_t>(kSamples, P.rows());
  const double n = static_cast<double>(P.rows());
  const double fitting = (static_cast<double>(limit) / n - kBytesPerPoint) / (4.0 * 1.05);
  char mean[32];
  std::snprintf(mean, sizeof mean, "%.0f", e.mean_neighbors);
  std::string advice = "use a smaller --radius (neighbors grow as r squared)";
  if (fitting >= 3.0)
    advice += ", or --max-neighbors " + std::to_string(static_cast<long long>(fitting * 0.9));
  throw ResourceLimitError(
      std::string("the neighborhoods would need ") + (early ? "at least " : "about ") +
      memory_size_text(e.bytes) + " (" + mean + " neighbors per point on average, counted on " +
      std::to_string(e.sampled) + " sample point" + (e.sampled == 1 ? "" : "s") + ", for " +
      std::to_string(P.rows()) + " points), more than the memory limit of " +
      memory_size_text(static_cast<double>(limit)) + "; " + advice +
      ", or raise --memory-limit (default 80% of the physical memory)");
}

// The method on points already in spatial order (see remove_texture).
RemoveTextureResult remove_texture_ordered(const Positions& P, Normals normals,
                                           const TriangleIndices& T,
                                           const RemoveTextureParams& params,
                                           const PipelineObserver& observer,
                                           RemoveTextureResult result) {
  const std::size_t n = static_cast<std::size_t>(P.rows());
  RemoveTextureReport& rep = result.report;
  rep.diagonal = bounding_box_diagonal(P);
  if (!(rep.diagonal > 0.0))
    throw std::invalid_argument("all points coincide: the cloud has no extent to filter");
  if (params.radius.unit == Length::Unit::Texture) {
    StageClock clock(observer, rep, "estimate scale");
    rep.scale = estimate_texture_scale(P, normals, params.scale);
    rep.scale_estimated = true;
  }
  {
    const RadiusChoice choice = choose_radius(params, rep.diagonal, rep.scale);
    rep.radius = choice.radius;
    rep.radius_choice = choice.choice;
    rep.radius_reason = choice.reason;
    if (choice.choice == "fallback")
      warn(observer, rep.scale.reason + "; r = " + number_text(rep.radius) +
                         " (the fallback) is used: the run smooths the surface at that scale "
                         "but has no texture to remove. Give -r to choose a scale yourself.");
  }
  if (!params.allow_large_radius) {
    // A neighbor cap bounds what is kept (the k nearest), so it bounds this too.
    double count = estimate_neighbor_count(P, rep.radius);
    if (params.max_neighbors > 0) count = std::min(count, double(params.max_neighbors));
    const double share = count / static_cast<double>(n);
    if (share > params.max_neighbor_share || count > params.max_mean_neighbors)
      throw std::invalid_argument(
          "r = " + number_text(rep.radius) + " would put about " + number_text(std::round(count)) +
          " points (" + number_text(std::round(100.0 * share)) +
          "% of the cloud) in every neighborhood; memory and time grow as r², and a "
          "neighborhood that large filters the shape itself. Choose a smaller r, or force the "
          "run (--force on the command line)");
  }
  rep.lambda = params.lambda.resolve(rep.diagonal, rep.radius);
  rep.sigma_s = params.sigma_s.resolve(rep.diagonal, rep.radius);
  rep.sigma_p = params.sigma_p.resolve(rep.diagonal, rep.radius);

  Neighborhoods R;
  {
    StageClock clock(observer, rep, "neighborhoods");
    check_memory(P, params, rep);
    R = radius_neighborhoods(P, {rep.radius, params.max_neighbors}, clock.progress());
    rep.neighbors = neighborhood_stats(R, 3);
  }
  // (Not when a cap below the threshold is what keeps the neighborhoods small.)
  const bool capped_small =
      params.max_neighbors > 0 && params.max_neighbors < params.min_mean_neighbors;
  if (rep.neighbors.mean < params.min_mean_neighbors && !capped_small)
    warn(observer,
         "r = " + number_text(rep.radius) + " holds only " +
             number_text(std::round(rep.neighbors.mean * 10.0) / 10.0) +
             " neighbors per point on average, too few to tell texture from surface; "
             "r = " +
             number_text(rep.radius * std::sqrt(30.0 / std::max(rep.neighbors.mean, 1.0))) +
             " would hold about 30.");
  if (rep.neighbors.sparse_points > 0)
    warn(observer, std::to_string(rep.neighbors.sparse_points) +
                       " points have fewer than 3 neighbors within r; they keep their input "
                       "position and normal. Increase --radius if there are many.");

  // Normals: estimated on a small k-NN neighborhood, so that they describe the
  // textured surface (the filters expect that) and stay sharp at creases.
  // Input normals that are all zero (or were NaN: the reader zeroes those)
  // give no orientation to copy from neighbors: estimate them from the
  // positions, as when there are none.
  const bool have_normals = normals.rows() == P.rows() && (normals.array() != 0.0).any();
  if (normals.rows() == P.rows() && !have_normals) {
    rep.normals_reestimated = n;
    normals = Normals();
  }
  if (!have_normals || params.reorient) {
    StageClock clock(observer, rep, have_normals ? "orient normals" : "estimate normals");
    const Neighborhoods K = knn_neighborhoods(P, params.normal_neighbors);
    Normals raw;
    if (have_normals) {
      raw = reestimate_zero_normals(P, normals, K, &rep.normals_reestimated);
    } else {
      EstimateNormalsResult est = estimate_normals(P, K, clock.progress());
      raw = std::move(est.normals);
      rep.normals_degenerate = est.degenerate;
      rep.normals_estimated = true;
    }
    OrientNormalsResult oriented = orient_normals(P, raw, K, params.orient);
    rep.normals_flipped = oriented.flipped;
    result.input_normals = std::move(oriented.normals);
  } else {
    std::size_t zero = 0;
    for (std::size_t i = 0; i < n; ++i) zero += normals.row(i).squaredNorm() == 0.0;
    if (zero > 0) {
      StageClock clock(observer, rep, "re-estimate normals");
      const Neighborhoods K = knn_neighborhoods(P, params.normal_neighbors);
      result.input_normals = reestimate_zero_normals(P, normals, K, &rep.normals_reestimated);
    } else {
      result.input_normals = std::move(normals);
    }
  }
  rep.normals_degenerate = 0;
  for (std::size_t i = 0; i < n; ++i)
    rep.normals_degenerate += result.input_normals.row(i).squaredNorm() == 0.0;
  if (rep.normals_degenerate > 0)
    warn(observer, std::to_string(rep.normals_degenerate) +
                       " points have no usable normal (too few or collinear neighbors); they "
                       "take the filtered normal of their neighbors");
  // Over the nearest members of R_i, as many as orientation would use.
  rep.orientation_inconsistency = orientation_inconsistency(
      result.input_normals, R, static_cast<std::size_t>(params.normal_neighbors));
  if (have_normals && !params.reorient &&
      rep.orientation_inconsistency > kInconsistentOrientationThreshold)
    warn(observer, "the input normals look inconsistently oriented (" +
                       std::to_string(100.0 * rep.orientation_inconsistency) +
                       "% of neighbor pairs disagree); consider --reorient");

  if (params.sheets.max_angle_deg < 180.0 || params.thin_parts.min_radius_fraction < 1.0) {
    StageClock clock(observer, rep, "separate sheets");
    ShrinkToThinPartsParams tp = params.thin_parts;
    tp.radius = rep.radius;
    const ShrinkToThinPartsResult thin = shrink_to_thin_parts(R, P, result.input_normals, tp);
    rep.thin_part_points = thin.points;
    rep.thin_part_neighbors = thin.removed;
    rep.opposite_neighbors = drop_opposite_neighbors(R, P, result.input_normals, params.sheets);
  }
  if (T.rows() != 0 && params.mesh_paths.path_factor > 0.0) {
    StageClock clock(observer, rep, "follow the mesh");
    LimitNeighborhoodsToMeshParams mp = params.mesh_paths;
    mp.radius = rep.radius;
    const LimitNeighborhoodsToMeshResult kept = limit_neighborhoods_to_mesh(R, P, T, mp);
    rep.mesh_path_points = kept.points;
    rep.mesh_path_neighbors = kept.removed;
  }

  std::vector<float> omega;  // membership of Ω, for the filters
  // Of each point above its own fitted surface: for the global update's
  // anchors and for limit_sink_moves; empty when neither reads it.
  std::vector<float> own_height;
  const bool anchors_read_height =
      params.anchor_height > 0.0 && params.update.mode == UpdateMode::Global;
  {
    StageClock clock(observer, rep, "detect texture");
    DetectTextureParams tp = params.texture;
    tp.lambda = rep.lambda;
    tp.min_surface_radius = params.min_surface_radius.resolve(rep.diagonal, rep.radius);
    // Clouds only: on meshes the mesh-path limit keeps R_i on its sheet.
    const bool split = T.rows() == 0 && params.surface_split.max_angle_deg < 180.0;
    tp.surface_normals = split;
    TextureDetection det = detect_texture(P, result.input_normals, R, tp, clock.progress());
    if (split) {
      rep.surface_split_neighbors = drop_neighbors_across_surfaces(
          R, result.input_normals, det.surface_normal, det.is_texture, params.surface_split);
      Normals().swap(det.surface_normal);
    }
    result.is_texture = std::move(det.is_texture);
    omega = std::move(det.omega);
    rep.texture_points = det.texture_points;
    rep.no_plane = det.no_plane;
    rep.ransac_mean_iterations = det.mean_iterations;
    // Over the texture points: sparse features may be far fewer than 1% of
    // the cloud. Without texture, over all points.
    std::vector<float> heights;
    for (std::size_t i = 0; i < n; ++i)
      if (result.is_texture[i]) heights.push_back(det.height[i]);
    if (heights.empty()) heights = det.height;
    if (anchors_read_height || params.sinks.slack > 0.0) own_height = std::move(det.height);
    if (!heights.empty()) {
      const std::size_t at = (heights.size() - 1) * 99 / 100;
      std::nth_element(heights.begin(), heights.begin() + static_cast<std::ptrdiff_t>(at),
                       heights.end());
      rep.texture_height = heights[at];
    }
    if (params.move_limit > 0.0) rep.max_move = params.move_limit * rep.texture_height + rep.lambda;
  }

  Normals filtered;
  {
    StageClock clock(observer, rep, "gaussian filter");
    FilterNormalsGaussianParams gp = params.gaussian;
    gp.sigma_s = rep.sigma_s;
    GaussianFilterResult g = filter_normals_gaussian(P, result.input_normals, R, omega, gp);
    rep.empty_subneighborhoods = g.empty_subneighborhoods;
    filtered = std::move(g.normals);
  }
  {
    StageClock clock(observer, rep, "rolling filter");
    FilterNormalsRollingParams rp = params.rolling;
    rp.sigma_s = rep.sigma_s;
    RollingFilterResult r = filter_normals_rolling(P, result.input_normals, std::move(filtered), R,
                                                   omega, rp, clock.progress());
    rep.rolling_iterations = r.iterations;
    std::vector<float>().swap(omega);  // the update uses the hard labels
    filtered = std::move(r.normals);
  }
  UpdatePositionsParams up = params.update;
  up.sigma_p = rep.sigma_p;
  up.max_move = rep.max_move;
  up.anchor_height = params.anchor_height * rep.lambda;
  up.anchor_angle_deg = params.anchor_angle;
  up.solve_radius = params.solve_radius.resolve(rep.diagonal, rep.radius);
  LimitCounterMovesParams cp = params.counter_moves;
  cp.height = rep.texture_height;
  LimitTipMovesParams tp = params.tips;
  tp.radius = up.solve_radius;
  tp.lambda = rep.lambda;
  tp.ceiling = 0.0;  // the waves' second pass alone sets it (wave_ceiling)
  LimitSinkMovesParams sp = params.sinks;
  sp.radius = up.solve_radius;
  sp.lambda = rep.lambda;
  sp.height = rep.texture_height;
  const std::vector<float> no_height;
  const std::vector<float>& surface_height = anchors_read_height ? own_height : no_height;
  int relief_side = 0;  // the last pass's limit_counter_moves side, for keep_input_normals
  // released: the points whose anchors the waves pass lowered (empty on the
  // first pass), for limit_counter_moves.
  const auto keep_update = [&](UpdatePositionsResult&& u,
                               const std::vector<std::uint8_t>& released) {
    rep.update_isolated = u.isolated;
    rep.update_iterations = u.iterations;
    rep.mean_displacement = u.mean_displacement;
    rep.moves_limited = u.limited;
    LimitCounterMovesResult c =
        limit_counter_moves(P, u.positions, filtered, result.is_texture, cp, released);
    rep.relief_lean = c.lean;
    relief_side = c.side;
    rep.counter_moves_limited = c.limited;
    LimitTipMovesResult t = limit_tip_moves(P, c.positions, result.input_normals, R, tp);
    rep.tip_moves_limited = t.limited;
    if (sp.slack > 0.0) {
      LimitSinkMovesResult k =
          limit_sink_moves(P, t.positions, filtered, own_height, R, c.side > 0, sp);
      rep.sink_moves_limited = k.limited;
      t.positions = std::move(k.positions);
    }
    result.positions = std::move(t.positions);
  };
  {
    StageClock clock(observer, rep, "update positions");
    // The global solve reads only the part of R_i within the solve radius:
    // keep that part alone, so the solve's coefficients take the place of the
    // rest instead of adding to the peak memory.
    if (up.mode == UpdateMode::Global && up.solve_radius < rep.radius)
      shrink_neighborhoods(R, P, up.solve_radius);
    // Exact input normals for the update (update_input_normals): they stand
    // for the filtered ones from here on, unless the relief then reads as
    // sparse engraving, whose flat walls are as exact as facets.
    std::vector<std::pair<std::uint32_t, Eigen::RowVector3d>> replaced;
    if (params.update_input_normals && params.fit_normals && T.rows() == 0) {
      KeepInputNormalsParams kp = params.keep_input;
      kp.radius = up.solve_radius;
      kp.lambda = rep.lambda;
      take_exact_input_normals(P, result.input_normals, result.is_texture, R, kp, filtered,
                               replaced);
    }
    const auto first_pass = [&] {
      keep_update(update_positions(P, filtered, R, result.is_texture, surface_height,
                                   result.input_normals, up, clock.progress()),
                  {});
    };
    first_pass();
    rep.input_normals_updated = replaced.size();
    if (!replaced.empty() && relief_side < 0) {
      for (const auto& [i, row] : replaced) filtered.row(i) = row;
      rep.input_normals_updated = 0;
      first_pass();
    }
  }
  if (params.fit_normals && T.rows() == 0) {
    FitNormalsToPositionsResult fit;
    {
      StageClock clock(observer, rep, "fit normals");
      FitNormalsToPositionsParams fp = params.output_normals;
      fp.sigma = params.fit_sigma.resolve(rep.diagonal, rep.radius);
      fp.radius = params.solve_radius.resolve(rep.diagonal, rep.radius);
      // Estimated normals are smoothed like the filtered ones and noisier:
      // only normals that came with the input weigh the fit's range.
      fit = params.fit_range_input_normals && !rep.normals_estimated
                ? fit_normals_to_positions(result.positions, filtered, result.input_normals, R, fp)
                : fit_normals_to_positions(result.positions, filtered, R, fp);
      rep.normals_not_fitted = fit.kept;
      rep.normals_blended = fit.blended;
    }
    // The share of the surface points flagged as lying on waves left;
    // negative where the fit flags nothing (no blend, or waves_min_deg 0).
    double share = -1.0;
    std::size_t flagged = 0;
    if (!fit.waves.empty()) {
      std::size_t surface = 0;
      for (std::size_t i = 0; i < n; ++i) {
        surface += !result.is_texture[i];
        flagged += !result.is_texture[i] && fit.waves[i];
      }
      rep.waves_flagged = flagged;
      share = surface ? static_cast<double>(flagged) / surface : 0.0;
    }
    // Waves left in the positions (remove_texture.h, wave_share_low): run
    // the update again with the flagged points' anchors lowered to the
    // texture's and the other surface points' by wave_rest_anchor, from the
    // same filtered normals; the output normals stay the first pass's.
    if (up.mode == UpdateMode::Global && share >= 0.0) {
      const double t = params.wave_share_low < 1.0
                           ? share_ramp(share, params.wave_share_low, params.wave_share_high)
                           : 0.0;
      if (t > 0.0 && up.anchor_surface > up.anchor_texture) {
        StageClock clock(observer, rep, "update positions, waves");
        const float factor = static_cast<float>(std::pow(up.anchor_texture / up.anchor_surface, t));
        // Texture points keep the first pass's anchors.
        const float rest = static_cast<float>(std::pow(params.wave_rest_anchor, t));
        std::vector<float> scale(n, 1.0f);
        std::vector<std::uint8_t> released(n, 0);
        for (std::size_t i = 0; i < n; ++i) {
          if (result.is_texture[i]) continue;
          released[i] = fit.waves[i] != 0;
          scale[i] = released[i] ? factor : rest;
        }
        rep.waves_released = flagged;
        tp.ceiling = params.wave_ceiling;
        keep_update(update_positions(P, filtered, R, result.is_texture, surface_height,
                                     result.input_normals, scale, up, clock.progress()),
                    released);
      }
    }
    // No waves left (remove_texture.h, blend_share_low): the blend with the
    // open window, or mixed with the blend.
    if (share >= 0.0 && params.blend_share_high > 0.0 && fit.open.rows() > 0) {
      const double t = share_ramp(share, params.blend_share_low, params.blend_share_high);
      if (t == 0.0) {
        fit.normals = std::move(fit.open);
        rep.normals_blended = fit.open_blended;
      } else if (t < 1.0) {
        for (std::size_t i = 0; i < n; ++i) {
          const Eigen::RowVector3d mixed = (1.0 - t) * fit.open.row(i) + t * fit.normals.row(i);
          const double norm = mixed.norm();
          if (norm > 0.0) fit.normals.row(i) = mixed / norm;
        }
      }
    }
    filtered = std::move(fit.normals);
    if (params.keep_input.high > 0.0 || params.keep_input.exact_angle_deg > 0.0 ||
        params.keep_input.still_angle_deg > 0.0 || params.keep_input.reached_angle_deg > 0.0) {
      StageClock clock(observer, rep, "keep input normals");
      KeepInputNormalsParams kp = params.keep_input;
      kp.radius = params.solve_radius.resolve(rep.diagonal, rep.radius);
      kp.lambda = rep.lambda;
      kp.engraved = relief_side < 0;
      KeepInputNormalsResult k = keep_input_normals(P, result.positions, result.input_normals,
                                                    filtered, result.is_texture, R, kp);
      rep.input_normals_kept = k.kept;
      filtered = std::move(k.normals);
    }
  }
  result.normals = std::move(filtered);
  if (params.raised_cells.enabled) {
    StageClock clock(observer, rep, "lower raised cells");
    LowerRaisedCellsParams lp = params.raised_cells;
    lp.min_lean = params.counter_moves.engraved_min_lean;
    lp.min_share = params.counter_moves.engraved_share;
    lp.radius = up.solve_radius;
    lp.height = rep.texture_height;
    LowerRaisedCellsResult l = lower_raised_cells(P, result.positions, result.normals,
                                                  result.is_texture, rep.relief_lean, R, lp);
    rep.raised_cells_lowered = l.lowered;
    rep.raised_cells_limited = l.limited;
    rep.raised_cells_turned = l.turned;
    result.positions = std::move(l.positions);
  }
  result.texture_height.resize(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i)
    result.texture_height(static_cast<Eigen::Index>(i)) =
        (P.row(i) - result.positions.row(i)).dot(result.normals.row(i));
  return result;
}

template <class T>
std::vector<T> unpermute(const std::vector<T>& v, const std::vector<std::uint32_t>& order) {
  std::vector<T> out(v.size());
  for (std::size_t k = 0; k < order.size(); ++k) out[order[k]] = v[k];
  return out;
}

}  // namespace

namespace {

// For each point, the index of the first point at exactly the same position
// (itself if none): an open-addressing table of 4-byte slots, linear time.
// Returns false, leaving *first empty, when there are no duplicates.
bool find_exact_duplicates(const Positions& P, std::vector<std::uint32_t>* first) {
  const std::size_t n = static_cast<std::size_t>(P.rows());
  std::size_t size = 16;
  while (size < 2 * n) size *= 2;
  constexpr std::uint32_t kEmpty = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> table(size, kEmpty);
  std::vector<std::uint32_t> result;
  auto bits = [](double v) {
    v += 0.0;  // -0 and +0 are the same position
    std::uint64_t b;
    std::memcpy(&b, &v, sizeof b);
    return b;
  };
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t h = bits(P(i, 0)) * 0x9E3779B97F4A7C15ull;
    h = (h ^ (h >> 29) ^ bits(P(i, 1))) * 0xBF58476D1CE4E5B9ull;
    h = (h ^ (h >> 31) ^ bits(P(i, 2))) * 0x94D049BB133111EBull;
    h ^= h >> 32;
    std::size_t slot = static_cast<std::size_t>(h) & (size - 1);
    std::uint32_t rep = static_cast<std::uint32_t>(i);
    for (; table[slot] != kEmpty; slot = (slot + 1) & (size - 1)) {
      const std::uint32_t j = table[slot];
      if (P(j, 0) == P(i, 0) && P(j, 1) == P(i, 1) && P(j, 2) == P(i, 2)) {
        rep = j;
        break;
      }
    }
    if (table[slot] == kEmpty) table[slot] = rep;
    if (rep != i && result.empty()) {
      result.resize(n);
      for (std::size_t k = 0; k < i; ++k) result[k] = static_cast<std::uint32_t>(k);
    }
    if (!result.empty()) result[i] = rep;
  }
  *first = std::move(result);
  return !first->empty();
}

// Lengths in the cloud's units, times 2^shift (exact).
RemoveTextureParams scaled_lengths(RemoveTextureParams p, int shift) {
  for (Length* len : {&p.radius, &p.lambda, &p.sigma_s, &p.sigma_p, &p.solve_radius, &p.fit_sigma,
                      &p.min_surface_radius})
    if (len->unit == Length::Unit::Absolute) len->value = std::ldexp(len->value, shift);
  return p;
}

RemoveTextureResult remove_texture_unique(Positions P, Normals normals, TriangleIndices T,
                                          const RemoveTextureParams& params,
                                          const PipelineObserver& observer);

// remove_texture on a cloud, or on a mesh's vertices when T (#T by 3, may be
// empty) gives its triangles.
RemoveTextureResult remove_texture_vertices(Positions P, Normals normals, TriangleIndices T,
                                            const RemoveTextureParams& params,
                                            const PipelineObserver& observer);

// ignore_input_normals: drops the input's normals; true if there were any.
bool drop_ignored_normals(Normals& normals, const RemoveTextureParams& params) {
  if (!params.ignore_input_normals || normals.rows() == 0) return false;
  normals = Normals();
  return true;
}

}  // namespace

RemoveTextureResult remove_texture(Positions P, Normals normals, const RemoveTextureParams& params,
                                   const PipelineObserver& observer) {
  const bool ignored = drop_ignored_normals(normals, params);
  RemoveTextureResult result = remove_texture_vertices(std::move(P), std::move(normals),
                                                       TriangleIndices(), params, observer);
  result.report.normals_ignored = ignored;
  return result;
}

namespace {

RemoveTextureResult remove_texture_vertices(Positions P, Normals normals, TriangleIndices T,
                                            const RemoveTextureParams& params,
                                            const PipelineObserver& observer) {
  validate(params);
  const ScopedThreads threads(params.threads);
  const std::size_t n = static_cast<std::size_t>(P.rows());
  if (n == 0) throw std::invalid_argument("the point cloud is empty");
  if (normals.rows() != 0 && normals.rows() != P.rows())
    throw std::invalid_argument("there must be as many normals as points, or none");
  if (n >= std::numeric_limits<std::uint32_t>::max())
    throw std::invalid_argument("clouds of more than 2^32-1 points are not supported");

  // Exact duplicates (merged scans) made every neighborhood around them hold
  // all of them: 5000 copies of a point took 19 s, 10000 did not finish. An
  // exact duplicate adds no geometry, so the method runs on the distinct
  // positions (the first point's normal, or the first non-zero one) and every
  // copy gets the result of the first. Clouds without duplicates take the
  // path below unchanged.
  std::vector<std::uint32_t> first;
  if (find_exact_duplicates(P, &first)) {
    std::vector<std::uint32_t> unique_index(n);
    std::vector<std::uint32_t> unique_rows;
    for (std::size_t i = 0; i < n; ++i) {
      if (first[i] == i) {
        unique_index[i] = static_cast<std::uint32_t>(unique_rows.size());
        unique_rows.push_back(static_cast<std::uint32_t>(i));
      } else {
        unique_index[i] = unique_index[first[i]];
      }
    }
    const auto m = static_cast<Eigen::Index>(unique_rows.size());
    Positions UP(m, 3);
    Normals UN(normals.rows() != 0 ? m : 0, 3);
    for (Eigen::Index k = 0; k < m; ++k) UP.row(k) = P.row(unique_rows[k]);
    if (UN.rows() != 0) {
      UN.setZero();
      for (std::size_t i = 0; i < n; ++i) {
        auto row = UN.row(unique_index[i]);
        if (row.squaredNorm() == 0.0) row = normals.row(static_cast<Eigen::Index>(i));
      }
    }
    Normals input_normals = std::move(normals);
    for (Eigen::Index t = 0; t < T.rows(); ++t)
      for (int k = 0; k < 3; ++k)
        T(t, k) = static_cast<std::int32_t>(unique_index[static_cast<std::size_t>(T(t, k))]);
    RemoveTextureResult u =
        remove_texture_unique(std::move(UP), std::move(UN), std::move(T), params, observer);
    RemoveTextureResult result;
    result.report = std::move(u.report);
    result.report.duplicates_merged = n - unique_rows.size();
    result.positions.resize(static_cast<Eigen::Index>(n), 3);
    result.normals.resize(static_cast<Eigen::Index>(n), 3);
    result.input_normals.resize(static_cast<Eigen::Index>(n), 3);
    result.is_texture.resize(n);
    result.texture_height.resize(static_cast<Eigen::Index>(n));
    for (std::size_t i = 0; i < n; ++i) {
      const auto r = static_cast<Eigen::Index>(i);
      const Eigen::Index k = unique_index[i];
      result.positions.row(r) = u.positions.row(k);
      result.normals.row(r) = u.normals.row(k);
      // A copy keeps its own input normal where it had a usable one.
      result.input_normals.row(r) =
          input_normals.rows() != 0 && input_normals.row(r).squaredNorm() != 0.0
              ? Eigen::RowVector3d(input_normals.row(r))
              : Eigen::RowVector3d(u.input_normals.row(k));
      result.is_texture[i] = u.is_texture[static_cast<std::size_t>(k)];
      result.texture_height(r) = u.texture_height(k);
    }
    std::size_t texture = 0;
    for (const std::uint8_t t : result.is_texture) texture += t;
    result.report.texture_points = texture;
    result.input_positions = std::move(P);
    return result;
  }
  return remove_texture_unique(std::move(P), std::move(normals), std::move(T), params, observer);
}

RemoveTextureResult remove_texture_unique(Positions P, Normals normals, TriangleIndices T,
                                          const RemoveTextureParams& original_params,
                                          const PipelineObserver& observer) {
  const std::size_t n = static_cast<std::size_t>(P.rows());
  // Clouds whose extent is beyond 2^±64 are scaled by a power of two (exact)
  // so that squared distances neither overflow (±1e300 coordinates) nor
  // underflow (±1e-300), and scaled back at the end. Other clouds are
  // untouched.
  int shift = 0;
  {
    const double d = bounding_box_diagonal(P);
    if (d > 0.0 && std::isfinite(d) && (d > 0x1p64 || d < 0x1p-64)) shift = -std::ilogb(d);
  }
  const RemoveTextureParams params =
      shift == 0 ? original_params : scaled_lengths(original_params, shift);
  Positions original;  // kept whole, since scaling back could round a coordinate
  if (shift != 0) {
    original = P;
    P *= std::ldexp(1.0, shift);
  }

  // Work on the points in Morton order, so that neighbors are near each other
  // in memory (3-4x faster on clouds stored in random order), and give the
  // results back in the caller's order.
  RemoveTextureResult result;
  std::vector<std::uint32_t> order;
  Positions ordered_P;
  Normals ordered_N;
  {
    StageClock clock(observer, result.report, "spatial order");
    order = spatial_order(P);
    ordered_P = permute_rows(P, order);
    if (normals.rows() != 0) ordered_N = permute_rows(normals, order);
    P = Positions();  // the ordered copies hold them now
    normals = Normals();
    if (T.rows() != 0) {
      std::vector<std::uint32_t> rank(order.size());
      for (std::size_t k = 0; k < order.size(); ++k) rank[order[k]] = static_cast<std::uint32_t>(k);
      for (Eigen::Index t = 0; t < T.rows(); ++t)
        for (int k = 0; k < 3; ++k)
          T(t, k) = static_cast<std::int32_t>(rank[static_cast<std::size_t>(T(t, k))]);
    }
  }
  result = remove_texture_ordered(ordered_P, std::move(ordered_N), T, params, observer,
                                  std::move(result));
  result.positions = unpermute_rows(result.positions, order);
  result.normals = unpermute_rows(result.normals, order);
  result.input_normals = unpermute_rows(result.input_normals, order);
  result.is_texture = unpermute(result.is_texture, order);
  result.input_positions = unpermute_rows(ordered_P, order);
  Eigen::VectorXd height(static_cast<Eigen::Index>(n));
  for (std::size_t k = 0; k < n; ++k) height(order[k]) = result.texture_height(k);
  result.texture_height = std::move(height);
  if (shift != 0) {
    const double back = std::ldexp(1.0, -shift);
    result.positions *= back;
    result.input_positions = std::move(original);
    result.texture_height *= back;
    RemoveTextureReport& r = result.report;
    for (double* len :
         {&r.diagonal, &r.radius, &r.lambda, &r.sigma_s, &r.sigma_p, &r.mean_displacement,
          &r.texture_height, &r.max_move, &r.scale.spacing, &r.scale.noise, &r.scale.texture_radius,
          &r.scale.texture_height, &r.scale.thin_radius})
      *len *= back;
    for (double& len : r.scale.radii) len *= back;
    for (double& len : r.scale.residual) len *= back;
    for (double& len : r.scale.relief) len *= back;
  }
  return result;
}

}  // namespace

// Meshes (issue 13): the faces give the normals and bound the update.
RemoveTextureResult remove_texture(Positions P, Normals normals, const FaceList& faces,
                                   const RemoveTextureParams& params,
                                   const PipelineObserver& observer) {
  if (faces.size() == 0) return remove_texture(std::move(P), std::move(normals), params, observer);
  for (const std::uint32_t i : faces.indices)
    if (i >= static_cast<std::uint64_t>(P.rows()))
      throw std::invalid_argument("a face refers to vertex " + std::to_string(i) +
                                  ", but there are " + std::to_string(P.rows()));
  const bool ignored = drop_ignored_normals(normals, params);
  RemoveTextureReport mesh_report;
  TriangleIndices T = triangulate_faces(faces);
  bool from_faces = false;
  std::size_t reoriented = 0;
  {
    StageClock clock(observer, mesh_report, "face normals");
    reoriented = orient_triangles(P, T);
    if (params.use_faces && normals.rows() == 0) {
      normals = face_normals(P, T, params.face_normals);
      from_faces = true;
    }
  }
  // The paper's mode (use_faces false) treats the vertices as a cloud.
  RemoveTextureResult result = remove_texture_vertices(
      std::move(P), std::move(normals), params.use_faces ? T : TriangleIndices(), params, observer);
  RemoveTextureReport& rep = result.report;
  rep.mesh = true;
  rep.normals_ignored = ignored;
  rep.normals_from_faces = from_faces;
  rep.triangles = static_cast<std::size_t>(T.rows());
  rep.triangles_reoriented = reoriented;
  {
    StageClock clock(observer, rep, params.use_faces ? "repair folds" : "measure folds");
    RepairFoldsParams repair = params.folds;
    repair.enabled = params.use_faces;
    result.positions =
        repair_folds(result.input_positions, result.positions, T, repair, &rep.folds);
    if (!params.use_faces) return result;  // the paper: only measured
    std::size_t isolated = 0;
    const Normals out = face_normals(result.positions, T, params.face_normals, &isolated);
    for (Eigen::Index i = 0; i < out.rows(); ++i) {
      if (out.row(i).squaredNorm() > 0.0) result.normals.row(i) = out.row(i);
      result.texture_height(i) =
          (result.input_positions.row(i) - result.positions.row(i)).dot(result.normals.row(i));
    }
  }
  rep.timings.insert(rep.timings.begin(), mesh_report.timings.begin(), mesh_report.timings.end());
  double moved = 0.0;
  for (Eigen::Index i = 0; i < result.positions.rows(); ++i)
    moved += (result.positions.row(i) - result.input_positions.row(i)).norm();
  rep.mean_displacement = moved / std::max<Eigen::Index>(1, result.positions.rows());
  return result;
}

}  // namespace detexture
