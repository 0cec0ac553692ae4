// Halos: ice-crystal halos (the 22 and 46 deg halos, sundogs, the parhelic circle, the
// circumzenithal and tangent arcs) from phase tables ray-traced once through hexagonal ice prisms,
// drawn where the Sun (or the Moon) lights the cirrus or a crystal layer the user sets.
// skyelements/halos/README.md.
//
//   processor.add(welkin::elements::makeElement("halos"));                 // Layer Foreground
//   processor.vars().set(welkin::elements::haloskeys::opticalDepth, 0.2);  // a crystal layer
//   // command line: welkin render --elements sky,clouds,halos --var clouds.preset=scattered-cirrus
//   //               or   --elements sky,halos --var halos.optical_depth=0.2 --out halo.png
//
// Crystals: hexagonal prisms (side length a, length along the c-axis = aspect x 2a), four
// populations mixed by halos.plates, halos.columns, halos.random, halos.parry (relative weights
// of their scattering; unset: halos.preset's):
//   plates  c-axis vertical, tilted by a 2-D Gaussian of sigma halos.tilt_rad (aspect halos.plate_aspect)
//   columns c-axis horizontal (random azimuth, elevation spread halos.tilt_rad), free spin about it
//   random  uniformly random orientation (aspect halos.column_aspect)
//   parry   c-axis horizontal and two side faces horizontal (spread halos.tilt_rad)
// Geometric optics: unpolarised Fresnel reflection and refraction at every face (a ray splits by
// chance with the Fresnel probability, so no energy is lost), total internal reflection, no
// absorption, no diffraction; the refractive index of ice per channel (iceRefractiveIndex()).
// The Sun's disk (0.533 deg) is part of the trace.
//
// Radiance (cd/m^2) along a view ray that crosses the crystal layer (a thin shell at
// clouds.cirrus_height_m, default 9000 m): L = E p(view, light) (1 - exp(-tau_slant)), E the
// light's illuminance at the observer (lux per channel), p the mixed phase function (1/sr, from
// the table at the light's elevation), tau_slant = (halos.optical_depth + halos.cirrus_fraction x
// 0.3 x cirrus density) / max(|cos zenith|, 0.1) (0.3: the cirrus' optical depth at density 1, as
// the Clouds element draws it). The part from halos.optical_depth also attenuates what is behind
// (transmittance exp(-tau)); the cirrus' own attenuation is the Clouds element's. Light leaving
// within 1 deg of the light's direction (rays through two parallel faces) is not drawn: it stays
// in the direct beam. Nothing is drawn (no GL call) without light or crystals.
#pragma once
#include <welkin/element.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/gl/projection_programs.hpp>

#include <glm/glm.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace welkin::elements {

namespace haloskeys {
inline constexpr double kDeg = 0.017453292519943295;
inline const Key<std::string> preset{"halos.preset", Choices{{"common", "display", "random"}}, "crystal mix for the halos.plates/columns/random/parry nobody set: common (default: 22 deg halo, sundogs, arcs), display (a bright complex display), random (22 and 46 deg halos only)"};
inline const Key<double> opticalDepth{"halos.optical_depth", Range{0, 5}, "vertical optical depth of a crystal layer at the cirrus height, added to the cirrus' crystals (0: only the cirrus')"};
inline const Key<double> cirrusFraction{"halos.cirrus_fraction", Range{0, 1}, "share of the cirrus layer's optical depth due to halo-making crystals"};
inline const Key<double> plates{"halos.plates", Range{0, 1}, "weight of plate-oriented plates in the crystal mix (unset: the preset's)"};
inline const Key<double> columns{"halos.columns", Range{0, 1}, "weight of column-oriented columns in the crystal mix (unset: the preset's)"};
inline const Key<double> random{"halos.random", Range{0, 1}, "weight of randomly oriented crystals in the crystal mix (unset: the preset's)"};
inline const Key<double> parry{"halos.parry", Range{0, 1}, "weight of Parry-oriented columns in the crystal mix (unset: the preset's)"};
inline const Key<double> plateAspect{"halos.plate_aspect", Range{0.05, 1}, "plates' length along the c-axis over their diameter (2 x side)"};
inline const Key<double> columnAspect{"halos.column_aspect", Range{1, 8}, "columns' length along the c-axis over their diameter (also the random population's)"};
inline const Key<double> tilt{"halos.tilt_rad", Range{0.1 * kDeg, 10 * kDeg}, "spread (Gaussian sigma) of the oriented crystals' axes about their preferred orientation"};
inline const Key<std::string> tableQuality{"halos.table_quality", Choices{{"low", "default", "high"}}, "phase tables: low (CI tests), default, high (rays and resolution; skyelements/halos/README.md)"};
/// Frames over which the element's table (the real-time grid's and the per-pixel pass') is
/// re-interpolated to a moved light when
/// render.interactive is on (time running, a jump of the time): a second table is filled
/// 1/table_slices of its rows a frame while the one before is drawn, turned onto the current light
/// (skyelements/halos/README.md, "Time running"). 1, or render.interactive off: the whole table in
/// the frame the light moved past the tolerance.
inline const Key<int> tableSlices{"halos.table_slices", Range{1, 64},
                                  "frames over which the halo table follows a moved light (render.interactive; 1: at once)"};
inline constexpr int kTableSlicesDefault = 32;
}  // namespace haloskeys

namespace halos {

/// Real refractive index of ice at wavelength `nm` (nm, [350, 800]): a Cauchy fit n = A + B /
/// lambda^2 through 1.3072 at 656.3 nm and 1.3136 at 486.1 nm (ordinary ray, the values halo
/// texts tabulate, e.g. Tape 1994 "Atmospheric Halos"; within 1e-3 of Warren & Brandt 2008,
/// J. Geophys. Res. 113 D14220, over the visible). 1.3091 at 589 nm.
double iceRefractiveIndex(double nm);
/// The wavelengths traced for the red, green and blue channels, nm (the sRGB primaries' dominant).
inline constexpr std::array<double, 3> kChannelNm{612.0, 549.0, 465.0};

/// Minimum deviation of a prism of apex angle `apexRad` at index n: 2 asin(n sin(A/2)) - A
/// (rad). 60 deg, n = 1.31: 21.84 deg (the 22 deg halo); 90 deg: 45.70 deg (the 46 deg halo).
double minimumDeviationRad(double n, double apexRad);
/// Bravais' index for rays inclined by `elevationRad` to a prism's plane of refraction (skew
/// rays through a prism with a vertical edge): n' = sqrt(n^2 - sin^2 e) / cos e (Bravais 1847;
/// Tape 1994 §2; Greenler 1980 "Rainbows, Halos and Glories" app.).
double bravaisIndex(double n, double elevationRad);
/// Azimuth between the Sun and a parhelion (sundog) for the Sun at `sunElevationRad`: the
/// minimum deviation of the 60 deg prism at Bravais' index (rad; the sundog stays at the Sun's
/// elevation). 21.8 deg at 0, 28.7 deg at 30 deg (n = 1.31); none above 60.75 deg.
double parhelionAzimuthRad(double n, double sunElevationRad);
/// The sundog's angular distance from the Sun, rad: cos d = sin^2 h + cos^2 h cos(azimuth).
double parhelionDistanceRad(double n, double sunElevationRad);
/// Elevation of the circumzenithal arc's lowest point (light in through the top face, out of a
/// side face of a horizontal plate): sin e = sqrt(n^2 - cos^2 h) (rad); NaN when the arc cannot
/// form (h above the cut-off).
double circumzenithalElevationRad(double n, double sunElevationRad);
/// The Sun's elevation above which the circumzenithal arc cannot form: cos h = sqrt(n^2 - 1)
/// (rad): 32.2 deg at n = 1.31.
double circumzenithalCutoffRad(double n);

enum class Orientation { Random, Plate, Column, Parry };
struct Population {
    Orientation orientation = Orientation::Random;
    double aspect = 2.0;   ///< length along the c-axis over the diameter 2a, (0, 20]
    double tiltRad = 0.0;  ///< spread (Gaussian sigma) of the orientation, rad, [0, 0.3]
};

/// What a trace did: every ray leaves the crystal (energy is conserved by construction); rays
/// still inside after kMaxEvents internal events are counted and deposited where they head.
struct TraceStats {
    uint64_t rays = 0;
    uint64_t truncated = 0;
    double seconds = 0.0;
    /// Weight leaving the crystals over weight entering (traceOrientedExact: 1 when the Fresnel
    /// branches conserve energy; the other traces deposit each ray once: 1 by construction).
    double energyRatio = 1.0;
};
inline constexpr int kMaxEvents = 64;

/// The phase function of randomly oriented crystals over the scattering angle, `bins` bins over
/// [0, pi]; p[i] per channel in 1/sr (integral over the sphere 1).
struct Phase1D {
    std::vector<glm::dvec3> p;
    TraceStats stats;
    double binRad() const { return M_PI / double(p.size()); }
    /// Linear interpolation between bin centres at scattering angle theta (rad).
    glm::dvec3 at(double thetaRad) const;
    /// Integral over the sphere, per channel (1 up to rounding).
    glm::dvec3 integral() const;
};
/// Rays: `rays` in all (rays / 3 crystals, each traced at the three channels' indices with the
/// same random choices), seed: deterministic for a seed and a thread count
/// or not (chunks of rays seeded by their index, integer accumulation). threads 0: all cores.
Phase1D traceRandom(const Population& pop, int bins, uint64_t rays, uint64_t seed, int threads = 0);

/// The phase function of oriented crystals for the light at elevation `sunElevationRad`, over the
/// sky in the light's frame: elevation e in [-pi/2, pi/2] (`ne` bins) x azimuth from the light's
/// azimuth |phi| in [0, pi] (`na` bins; the pattern is symmetric about the light's vertical);
/// p[ie * na + ia] per channel in 1/sr.
struct Phase2D {
    int ne = 0, na = 0;
    std::vector<glm::dvec3> p;
    TraceStats stats;
    glm::dvec3 at(int ie, int ia) const { return p[std::size_t(ie) * std::size_t(na) + std::size_t(ia)]; }
    /// Elevation and azimuth of a bin centre, rad.
    double elevationRad(int ie) const { return -0.5 * M_PI + (ie + 0.5) * M_PI / ne; }
    double azimuthRad(int ia) const { return (ia + 0.5) * M_PI / na; }
    glm::dvec3 integral() const;
};
Phase2D traceOriented(const Population& pop, double sunElevationRad, int ne, int na, uint64_t rays, uint64_t seed,
                      int threads = 0);

/// The brute-force reference (skyelements/halos/README.md's accuracy check): every ray followed through every
/// Fresnel branch with its weight (no random choice at the faces), each crystal orientation and
/// entry point drawn as in the tables' trace; returns the same table.
Phase2D traceOrientedExact(const Population& pop, double sunElevationRad, int ne, int na, uint64_t rays, uint64_t seed,
                           int threads = 0);

/// Denoising a traced table (skyelements/halos/README.md, "Denoised tables"), done by
/// HaloTables::build before the tables are cached. Each bin's estimate is made over five kinds of
/// window about it: a square of (2r + 1)^2 bins (r <= kMaxRadius) and lines of 2r + 1 bins
/// (r <= kMaxLine) along the azimuth, the elevation and the two diagonals (the halos' arcs are
/// ridges a bin or two wide, which a line along them averages and a square cannot). Each window
/// grows while its mean stays consistent, within kGamma standard errors in every channel, with
/// the means of all its smaller sizes (intersection of confidence intervals), and stops once it
/// holds kTargetRays rays; the standard error is the rays' Poisson error, the table read as counts
/// (p x the bin's solid angle x rays / 3 crystals). The windows' means are weighted by their
/// inverse variance. A window stops where the table changes by more than its noise: the halos'
/// edges, the sundogs and the arcs stay in place (within a bin) while the faint sky is averaged.
/// Each channel is rescaled to its integral before (1). Deterministic; `rays` as given to the
/// trace (>= 3; throws welkin::Error otherwise). The 1-D table: lines of up to 2 kMaxLine + 1 bins.
struct Denoise {
    static constexpr int kMaxRadius = 4;
    static constexpr int kMaxLine = 8;
    static constexpr double kGamma = 1.5;
    static constexpr double kTargetRays = 10000.0;
};
void denoise(Phase2D& table, uint64_t rays);
/// The same over the scattering angle (windows of 2r + 1 bins, r <= 2 kMaxLine).
void denoise(Phase1D& table, uint64_t rays);

/// The element's tables: the three oriented populations at `slices` light elevations evenly
/// over [0, 90] deg, the random population's 1-D table.
struct HaloTables {
    struct Quality {
        std::string name;
        int ne = 256, na = 256, slices = 31;  ///< 2-D bins; light elevations (0, 3, ..., 90 deg)
        uint64_t raysPerSlice = 600000;       ///< per oriented population and light elevation
        uint64_t raysRandom = 3000000;        ///< the random population
        int bins = 1800;                      ///< 1-D bins (0.1 deg)
    };
    /// low (180 x 180 bins, 10 elevations, 60 000 rays: the tests), default (256 x 256, 31, 600 000),
    /// high (512 x 512, 46, 4 000 000); throws welkin::Error for another name.
    static Quality quality(const std::string& name);

    Quality q;
    double plateAspect = 0.2, columnAspect = 2.0, tiltRad = 1.0 * haloskeys::kDeg;
    std::vector<float> plates, columns, parry;  ///< [(slice * ne + ie) * na + ia] * 3 + c, 1/sr
    std::vector<float> random;                  ///< [bin * 3 + c], 1/sr
    double buildSeconds = 0.0;                  ///< wall time of the trace (0 when read from disk)
    bool fromCache = false;

    double sliceElevationRad(int s) const { return q.slices > 1 ? s * 0.5 * M_PI / (q.slices - 1) : 0.0; }
    uint64_t hash() const;
    /// Traced with all cores.
    static HaloTables build(const Quality& q, double plateAspect, double columnAspect, double tiltRad);
    /// From the disk cache ($XDG_CACHE_HOME/welkin, else ~/.cache/welkin, `halos-<hash>.bin`,
    /// the hash of the inputs and the code version), else built and written there atomically
    /// (temporary file + rename; a failed write is ignored). Kept in memory for the process.
    static const HaloTables& cached(const Quality& q, double plateAspect, double columnAspect, double tiltRad);
    static std::string cachePath(const HaloTables& t);

    /// The mixed table the shader samples: weights (plates, columns, random, parry) >= 0 with a
    /// positive sum (normalised here), RGBA per texel [(slice * ne + ie) * na + ia], 1/sr, with
    /// the forward 1 deg around the light set to 0.
    std::vector<glm::vec4> mix(const std::array<double, 4>& weights) const;
};

/// The preset's mix (plates, columns, random, parry) and cirrus fraction; throws welkin::Error
/// naming halos.preset for an unknown name.
struct HaloPreset {
    std::array<double, 4> weights;
    double cirrusFraction;
};
const HaloPreset& haloPreset(const std::string& name);

}  // namespace halos

class Halos final : public SkyElement {
public:
    Halos();
    /// True if the last render() issued its draw (false: no light or no crystals).
    bool drewLastFrame() const { return drew_; }
    /// The tables in use (nullptr before the first frame with light and crystals).
    const halos::HaloTables* tables() const { return tables_; }

private:
    void doInit(InitContext& ctx) override;
    void doValidateOptions(const SkyVars& vars) const override;
    void doRender(const FrameContext& ctx) override;
    void doRelease() override;
    void doStats(nlohmann::json& root) const override;

    gl::ProjectionPrograms programs_, gridPrograms_, finePrograms_, smoothPrograms_, cellPrograms_;
    gl::Texture2D table_;            // the mix at the light's elevation (azimuth x elevation), 1/sr (per-pixel path)
    gl::Texture2D octTable_;         // the grid path's table (octahedral half-sphere, the layer baked in): drawn
    gl::Texture2D octBack_;          // the one being filled over frames (halos.table_slices), swapped in when complete
    int tableUnit_ = 0;              // its private texture unit (SkyElement::textureUnit)
    gl::Buffer cloudUbo_;
    const halos::HaloTables* tables_ = nullptr;
    std::array<double, 4> mixed_{-1, -1, -1, -1};
    std::vector<glm::vec4> mix_;       // the plates' and Parry columns' part of the mix at every slice (HaloTables::mix)
    std::vector<glm::vec4> mixShift_;  // the columns' and random crystals' part
    // The per-pixel path's table refilled over frames as the grid's (halos.table_slices): tableBack_
    // filled ne / slices rows a frame (pix_, below) while table_ is drawn, turned onto the
    // light; swapped in when complete.
    gl::Texture2D tableBack_;
    std::vector<glm::vec4> tableRows_;   // the rows computed this frame (CPU), uploaded at once
    void updatePixelTable(double elevationRad, int slices);
    // Rows [r0, r1) of the per-pixel (azimuth, elevation) table at the light elevation `el`, into `target`.
    void fillPixelRows(gl::Texture2D& target, double el, int r0, int r1);
    bool drew_ = false;
    // A table refilled over frames (halos.table_slices; the grid's and the per-pixel path's):
    // the light elevation the drawn one holds, the refill of the other in progress, work counted.
    struct Refill {
        double held = NAN;             // the light elevation the drawn table holds, rad (NaN: none: filled whole next)
        double backElevation = 0.0;    // the one the other table is being filled for
        int backRow = -1;              // the next row of the other table to fill (-1: no refill in progress)
        double lastElevation = -10.0;  // the light's elevation in the last frame (a jump)
        int rowsLast = 0;              // rows computed in the last frame
        int refills = 0;               // refills started (whole or spread)
        double updateMs = 0.0;         // the last frame's work on the table, CPU ms
    };
    Refill oct_, pix_;  // the grid's table, the per-pixel path's
    // One frame of a table of n rows (halos.cpp); fill(back, el, r0, r1) computes rows [r0, r1) at
    // the light elevation el into the drawn table (back false) or the other; returns true when the
    // other is complete, to be swapped in.
    template <class Fill>
    static bool refillFrame(Refill& s, double el, bool whole, int slices, int n, Fill&& fill);
    // The grid path's table: for each of its N x N texels its place in the (azimuth, elevation)
    // table (fixed per table size), the layer's scattered
    // fraction and transmittance in its direction (per layer), and what it holds now.
    struct OctTexel {
        uint16_t a0, a1;  // the two azimuth bins
        float wa;         // the weight of a1
        float row;        // the elevation as a fractional row (bin centres at integers)
        float mu;         // the direction's sine of elevation
    };
    std::vector<OctTexel> octRemap_;
    std::vector<glm::vec2> octLayer_;
    int octN_ = 0;
    std::vector<glm::vec4> octRows_;  // the rows computed this frame (CPU), uploaded at once
    glm::dvec4 octLayerKey_{-1.0};  // tau, observer height, layer height, planet radius the layer holds
    bool forcePerPixel_ = false;
    void updateOctTable(double elevationRad, double tauUser, double h0, double layerH, double R, int slices);
    // Rows [r0, r1) of the grid's table at the light elevation `el`, into the drawn table (back
    // false) or the one being filled, and what of its maps they complete (updateOctMaps).
    void fillOctRows(bool back, double el, int r0, int r1);

    // The adaptive cells (skyelements/halos/README.md, "Adaptive cells"). Made with the
    // grid's table, as its rows are filled (so a refill spread over frames spreads them too): the
    // table's means over blocks of kMapBlock^2 texels (M x M, M = N / kMapBlock) and per block the
    // largest |table - bilinear mean| over the block and its eight neighbours, per channel; drawn
    // and being filled, swapped with the table. The CPU copy of the table being filled, its block
    // rows done so far (means, deviations, detail), the per-block deviation.
    gl::Texture2D octMean_, octMeanBack_, octDetail_, octDetailBack_;
    int meanUnit_ = 0, detailUnit_ = 0, cellsSsbo_ = 0;
    std::vector<glm::vec4> octCpu_, blkMean_, blkDev_, blkDetail_;
    int mapMeanRows_ = 0, mapDevRows_ = 0, mapDetailRows_ = 0;
    bool frontMaps_ = false, backMaps_ = false;  // the drawn table's maps / the one being filled's are whole (made while on)
    void updateOctMaps(bool back, int r0, int r1);
    // The cells' lists (halos_cells.comp.glsl): two indirect draw commands, then the two lists of
    // pieces; rebuilt only when what they depend on changed (the view, the table's frame, the
    // drawn table, the layer's horizon, the tolerance).
    gl::Buffer cellBuf_;
    uint32_t listSize_ = 0;
    bool adaptive_ = true;
    // The fetching pieces' table (halos_fine.comp.glsl): the drawn grid table resampled
    // bilinearly on the GPU onto fineScale_ x its texels per axis whenever the drawn table
    // changes (octVersion_), read nearest-texel; 0: the pieces fetch the table itself bilinearly.
    gl::Program fineProgram_;
    gl::Texture2D octFine_;
    int fineImage_ = 0;
    int fineScale_ = kFineScale;
    uint64_t fineVersion_ = ~uint64_t(0);
    int fineMade_ = 0;
    double fineMs_ = 0.0;
    void updateFineTable();
    double cellTolerance_ = kCellTolerance;
    uint64_t octVersion_ = 0;  // bumped whenever the drawn grid table (and its maps) changes
    std::vector<double> cellsKey_, lastKey_;  // what the lists were made for; what the last frame's view was
    bool restOnly_ = true;                    // lists made only for a view that rests a frame
    bool listsDrawn_ = false;                 // the last frame drew the two lists (false: every cell fetched)
    std::array<uint32_t, 2> listVertices_{};  // the two lists' vertex counts (6 a piece), read back when made
    double cellsMs_ = 0.0;

public:
    /// The light's motion in elevation (rad) that re-interpolates the table between its slices
    /// (0.02 deg: 1/27 of the Sun's diameter).
    static constexpr double kElevationTolerance = 3.5e-4;
    /// The real-time display's grid cell, pixels (perspective projection, no cirrus): each vertex
    /// passes the unnormalised view ray, affine in the pixel, so the cells only bound the work;
    /// 64-pixel cells (llvmpipe rasterises per triangle: small cells cost, skyelements/rainbow/README.md).
    static constexpr int kGridCellPx = 64;
    /// The grid path's table is N x N with N = kOctScale x the (azimuth, elevation) table's
    /// azimuth bins (an octahedral map of the half sky y >= 0 in the light's frame, finer than
    /// the source's bins so that the resampling keeps most of its detail: skyelements/halos/README.md).
    static constexpr double kOctScale = 2.0;
    /// The adaptive cells' maps: one block per kMapBlock^2 texels of the grid's table.
    static constexpr int kMapBlock = 4;
    /// A piece of the grid is drawn from its corners' values (no fetch per pixel) where the
    /// difference from the per-pixel fetch is bounded by kCellTolerance x what the pixel shows
    /// (the halo light and, under it, a lower bound of the clear sky's light: kSkyFloor),
    /// per colour channel and in the transmittance (skyelements/halos/README.md). 10 %: a
    /// smooth piece's pixel stays within 11 % (t / (1 - t)) of the fetched value, at most 13
    /// 8-bit codes at the sRGB curve's steepest (117 codes per unit of ln L), inside the image
    /// tests' 10 %; at 3 % the default tables' grain leaves too few pieces smooth to save
    /// anything (0.004, half a code, until 2026-11-28, when the cells were off by default).
    static constexpr double kCellTolerance = 0.1;
    /// A lower bound of the clear sky's radiance above the horizon over the illuminance (at the
    /// observer) of the light that makes it, per channel (1/sr): single Rayleigh scattering by the
    /// zenith column (the shortest) at 90 deg from the light (the phase function's least, 3 / (16
    /// pi)), tau_R exp(-tau_R) 3 / (16 pi), with the sea-level Rayleigh optical depth at the
    /// channels' wavelengths (Hansen & Travis 1974: 0.063, 0.098, 0.193 at 612, 549, 465 nm).
    /// A bound from that physics alone (aerosols and multiple scattering only add light); not
    /// compared with the Sky element's rendered sky by a test.
    static constexpr std::array<double, 3> kSkyFloor{0.0035, 0.0053, 0.0095};
    /// The adaptive cells, on by default since 2026-11-28 (issue 21 item 4; skyelements/halos/README.md,
    /// "The default display"): for a view that rests a frame, the pieces that pass the cells'
    /// test (kCellTolerance) are drawn from their corners and the others fetch the table
    /// bilinearly per pixel; a view that moves (or time running) draws every cell fetching.
    /// Off: every cell fetches in every frame, one draw (the display before; setDisplayProbe's
    /// probes draw only then).
    void setAdaptiveCells(bool on) { adaptive_ = on; }
    /// The fetching pieces may read a copy of the grid's table kFineScale x finer per axis
    /// instead (resampled bilinearly on the GPU each time the drawn table changes), nearest-texel
    /// (setFineScale). Off by default (0): measured on llvmpipe, reading the 2 x finer copy (8 MB
    /// of RGBA16F for the default tables, 4 x the table's 2 MB) nearest-texel costs nearly what
    /// the bilinear fetch of the table costs (the memory it touches), and its image is further
    /// from the per-pixel pass (skyelements/halos/README.md, "The default display").
    static constexpr int kFineScale = 0;
    /// Tests and benchmarks: the fine table's scale, 1-4 (1: a copy of the table itself, read
    /// nearest), or 0: the fetching pieces fetch the table bilinearly (the default). Throws
    /// welkin::Error outside [0, 4].
    void setFineScale(int scale);
    /// Fine tables made so far (each one GPU pass over its texels) and the CPU time of issuing
    /// the last (ms; the GPU's work is in the element's render_ms with timing on).
    int fineTablesMade() const { return fineMade_; }
    /// Tests: make the cells' lists in every frame whose view changed too (false), not only for a
    /// view that rests a frame (true, the default: a moving view draws every cell fetching).
    void setCellsAtRestOnly(bool on) { restOnly_ = on; }
    /// True if the last frame drew the adaptive cells' two lists (false: every cell fetched).
    bool cellsDrawnLastFrame() const { return listsDrawn_; }
    /// Tests and benchmarks: another tolerance than kCellTolerance, a fraction in (0, 1] (throws
    /// welkin::Error outside it, NaN included).
    void setCellTolerance(double t);
    /// What the last grid frame drew with the adaptive cells, read back from the GPU (a stall:
    /// tests and benchmarks only): the pixels drawn from their corners, the pixels that fetch
    /// (below the horizon too: clipped there), the pieces of each list.
    struct CellCounts {
        long smoothPixels = 0, fetchPixels = 0;
        int smoothLeaves = 0, fetchLeaves = 0;
    };
    CellCounts readCellCounts(const Camera& camera) const;
    /// True if the last render() drew through the grid.
    bool gridLastFrame() const { return grid_; }
    /// The grid's table: rows computed in the last render() (work counted, not timed: N a whole
    /// table, N / halos.table_slices rounded up a slice of a refill, 0 none), refills started so
    /// far, its size N, and the light elevation the drawn table holds (rad; NaN: none yet).
    int gridRowsLastFrame() const { return oct_.rowsLast; }
    int gridRefills() const { return oct_.refills; }
    int gridTableSize() const { return octN_; }
    double gridTableElevation() const { return oct_.held; }
    /// The drawn grid table's texels (RGBA16F read back as float, N x N; tests: a table filled
    /// over frames against one filled whole).
    std::vector<float> readGridTable() const;
    /// The per-pixel path's (azimuth, elevation) table (every projection but the perspective grid's,
    /// and cirrus): the same as the grid's, in rows of the table (ne a whole table, ne /
    /// halos.table_slices rounded up a slice of a refill, 0 none), its rows, the light elevation
    /// the drawn table holds (rad; NaN: none yet) and its texels (RGBA16F read back as float, na x ne).
    int pixelRowsLastFrame() const { return pix_.rowsLast; }
    int pixelRefills() const { return pix_.refills; }
    int pixelTableRows() const { return table_ ? table_.height() : 0; }
    double pixelTableElevation() const { return pix_.held; }
    std::vector<float> readPixelTable() const;
    /// A motion of the light's elevation from one frame to the next beyond which a refill in
    /// progress is restarted at the new elevation (a new time, not time running: at 1440x and 30
    /// frames/s the Sun's elevation moves at most 0.2 deg a frame): 1 deg.
    static constexpr double kElevationJump = 0.01745;
    /// Tests and benchmarks: draw every view through the per-pixel pass (the offline path), to
    /// compare the grid with it.
    void setForcePerPixel(bool on) { forcePerPixel_ = on; }
    /// Benchmarks and tests only, not an image path: what a cheaper real-time display would cost
    /// at least on this machine (skyelements/halos/README.md, "What any route costs at least").
    /// The grid (perspective, no cirrus, adaptive cells off) drawn in pieces of `cellPx` pixels
    /// (kGridCellPx by default) either fetching the table per pixel (Fetch: the default display
    /// when cellPx is kGridCellPx), fetching it nearest-texel (Nearest: no bilinear filter), or
    /// from each piece's corners, interpolated, no fetch per pixel (Corners: every piece as the
    /// adaptive cells' smooth ones, whatever the table; a halo narrower than a piece is smeared).
    /// Throws welkin::Error for cellPx outside [8, 1024].
    /// Fine: every piece reading the fine table nearest-texel (setFineScale, > 0), as the
    /// default display's fetching pieces do.
    enum class DisplayProbe { Fetch, Nearest, Corners, Fine };
    void setDisplayProbe(DisplayProbe probe, int cellPx = kGridCellPx);

private:
    bool grid_ = false;
    DisplayProbe probe_ = DisplayProbe::Fetch;
    int probeCellPx_ = kGridCellPx;
};

}  // namespace welkin::elements
