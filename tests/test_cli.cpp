// The detexture command as a user runs it: files in, files out, exit codes.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_fixture.h"
#include "detexture/io/read_point_cloud.h"
#include "detexture/io/write_point_cloud.h"
#include "png_support.h"
#include "test_support.h"

namespace fs = std::filesystem;

namespace detexture {
namespace {

class Cli : public test::CliFixture {
 protected:
  Cli() : CliFixture("detexture_cli_") {}

  // A plane with a bump: small, fast, and the answer is known.
  PointCloud bumpy(bool normals) const {
    const auto s = test::bumpy_plane(41, 0.03, 0.05);
    PointCloud c;
    c.positions = s.P;
    if (normals) c.normals = s.N;
    return c;
  }

  void write_text(const std::string& name, const std::string& text) const {
    std::ofstream(path(name), std::ios::binary) << text;
  }
};

int lines(const std::string& text) {
  int n = 0;
  for (char c : text) n += c == '\n';
  return n;
}

// --version names the version and the commit; `detexture help [COMMAND]` is
// `--help` word for word, and --help shows examples.
TEST_F(Cli, VersionAndHelpAlias) {
  auto stdout_text = [&] {
    std::ifstream in(path("stdout.txt"));
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  ASSERT_EQ(run("--version"), 0);
  const std::string version = stdout_text();
  EXPECT_EQ(version.rfind("detexture 0.", 0), 0u) << version;
  EXPECT_NE(version.find("(commit "), std::string::npos) << version;
  EXPECT_EQ(version.find("commit unknown"), std::string::npos) << "built from a git checkout";
  ASSERT_EQ(run("--help"), 0);
  const std::string help = stdout_text();
  EXPECT_NE(help.find("Examples:"), std::string::npos);
  EXPECT_NE(help.find("--scale-report"), std::string::npos);
  ASSERT_EQ(run("help"), 0);
  EXPECT_EQ(stdout_text(), help);
  ASSERT_EQ(run("synth --help"), 0);
  const std::string synth_help = stdout_text();
  ASSERT_EQ(run("help synth"), 0);
  EXPECT_EQ(stdout_text(), synth_help);
  EXPECT_EQ(run("help nonsense"), 2);
}

TEST_F(Cli, PlainXyzInputGetsNormalsAndTextureRemoved) {
  write_point_cloud(path("in.xyz"), bumpy(false));
  ASSERT_EQ(run(path("in.xyz") + " -o " + path("out.ply") + " -r 0.2"), 0) << stderr_;
  const PointCloud out = read_point_cloud(path("out.ply"));
  ASSERT_EQ(out.size(), 41u * 41u);
  ASSERT_TRUE(out.has_normals());
  EXPECT_LT(out.positions.col(2).cwiseAbs().maxCoeff(), 0.01) << "the bump is gone";
  EXPECT_NE(stderr_.find("summary:"), std::string::npos);
  EXPECT_NE(stderr_.find("neighbors per point"), std::string::npos);
}

TEST_F(Cli, ColorsAndOtherPropertiesSurvive) {
  PointCloud c = bumpy(true);
  std::vector<double> red(c.size()), label(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) {
    red[i] = static_cast<double>(i % 256);
    label[i] = -static_cast<double>(i);
  }
  c.extras.push_back({"red", ScalarType::UInt8, red});
  c.extras.push_back({"label", ScalarType::Int32, label});
  write_point_cloud(path("in.ply"), c);
  ASSERT_EQ(run(path("in.ply") + " -o " + path("out.ply") + " -r 0.2 -q"), 0) << stderr_;
  EXPECT_EQ(stderr_, "") << "--quiet is quiet";
  const PointCloud out = read_point_cloud(path("out.ply"));
  ASSERT_EQ(out.extras.size(), 2u);
  EXPECT_EQ(out.extras[0].name, "red");
  EXPECT_EQ(out.extras[0].type, ScalarType::UInt8);
  EXPECT_EQ(out.extras[0].values, red);
  EXPECT_EQ(out.extras[1].type, ScalarType::Int32);
  EXPECT_EQ(out.extras[1].values, label);
}

TEST_F(Cli, TextureFieldsAndLayer) {
  write_point_cloud(path("in.ply"), bumpy(true));
  ASSERT_EQ(run(path("in.ply") + " -o " + path("out.ply") + " -r 0.2 --texture-fields" +
                " --texture-layer " + path("layer.ply")),
            0)
      << stderr_;
  const PointCloud out = read_point_cloud(path("out.ply"));
  const PointCloud layer = read_point_cloud(path("layer.ply"));
  ASSERT_EQ(out.extras.size(), 2u);
  EXPECT_EQ(out.extras[0].name, "texture");
  EXPECT_EQ(out.extras[1].name, "texture_height");
  ASSERT_EQ(layer.extras.size(), 1u);
  EXPECT_EQ(layer.extras[0].name, "texture_height");
  EXPECT_EQ(layer.positions, bumpy(true).positions) << "the layer sits on the input";
  // The bump's top carries most of its height (0.03) as texture; the border,
  // none.
  const std::size_t top = 20 * 41 + 20;
  EXPECT_GT(layer.extras[0].values[top], 0.02);
  EXPECT_LT(std::abs(layer.extras[0].values[0]), 0.002);
}

TEST_F(Cli, SameBytesOnOneAndTwoThreads) {
  write_point_cloud(path("in.xyz"), bumpy(false));
  ASSERT_EQ(run(path("in.xyz") + " -o " + path("a.ply") + " -r 0.2 --threads 1"), 0);
  ASSERT_EQ(run(path("in.xyz") + " -o " + path("b.ply") + " -r 0.2 --threads 2"), 0);
  std::ifstream a(path("a.ply"), std::ios::binary), b(path("b.ply"), std::ios::binary);
  const std::string sa((std::istreambuf_iterator<char>(a)), {}),
      sb((std::istreambuf_iterator<char>(b)), {});
  EXPECT_EQ(sa, sb);
}

// Every class of bad input: exit code 3, one line naming the file, no output.
TEST_F(Cli, BadInputsGiveOneLineErrorsAndNoOutput) {
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
      "property float y\nproperty float z\nend_header\n";
  const std::string binary_header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nend_header\n";
  const struct {
    const char* name;
    std::string content;
  } cases[] = {
      {"truncated.ply", binary_header + std::string(20, '\0')},
      {"count.ply", header + "0 0 0\n"},
      {"token.xyz", "0 0 0\n1 abc 0\n"},
      {"nan.xyz", "0 0 0\nnan 1 1\n"},
      {"inf.ply", header + "0 0 0\n1 inf 0\n"},
      {"noz.ply",
       "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
       "end_header\n0 0\n"},
      {"empty.xyz", "# nothing here\n"},
      {"header.ply", "ply\nformat ascii 2.0\nend_header\n"},
      {"magic.ply", "PLX\n"},
      {"unknown.abc", "0 0 0\n"},
  };
  for (const auto& c : cases) {
    write_text(c.name, c.content);
    const std::string out = path(std::string(c.name) + ".out.ply");
    EXPECT_EQ(run(path(c.name) + " -o " + out), 3) << c.name << ": " << stderr_;
    EXPECT_EQ(lines(stderr_), 1) << c.name << ": " << stderr_;
    EXPECT_NE(stderr_.find(c.name), std::string::npos) << stderr_;
    EXPECT_FALSE(fs::exists(out)) << c.name;
  }
  EXPECT_EQ(run(path("missing.ply") + " -o " + path("o.ply")), 3);
  EXPECT_EQ(lines(stderr_), 1);
}

TEST_F(Cli, NeverOverwritesWithoutAsking) {
  write_point_cloud(path("in.ply"), bumpy(true));
  const auto size = fs::file_size(path("in.ply"));
  EXPECT_EQ(run(path("in.ply") + " -o " + path("in.ply") + " --force"), 4);
  EXPECT_EQ(run(path("in.ply") + " -o " + dir_.string() + "/./in.ply --force"), 4);
  EXPECT_EQ(fs::file_size(path("in.ply")), size);
  write_text("taken.ply", "keep me");
  EXPECT_EQ(run(path("in.ply") + " -o " + path("taken.ply") + " -r 0.2"), 4);
  EXPECT_NE(stderr_.find("--force"), std::string::npos);
  EXPECT_EQ(fs::file_size(path("taken.ply")), 7u);
  EXPECT_EQ(run(path("in.ply") + " -o " + path("taken.ply") + " -r 0.2 --force"), 0);
}

// The modes change only the normals where the update fits the filtered
// normals (--update-filtered-normals). By default it fits the exact input
// normals the fitted output would keep; the filtered output keeps none, so
// there the update is the same as with the flag.
TEST_F(Cli, OutputNormalModesChangeOnlyTheNormals) {
  write_point_cloud(path("in.ply"), bumpy(true));
  const std::string filtered_update = " --update-filtered-normals";
  ASSERT_EQ(run(path("in.ply") + " -o " + path("default.ply") + " -r 0.2" + filtered_update), 0)
      << stderr_;
  for (const char* mode : {"blended", "fitted", "filtered"})
    ASSERT_EQ(run(path("in.ply") + " -o " + path(std::string(mode) + ".ply") +
                  " -r 0.2 --output-normals " + mode + " --stats " +
                  path(mode + std::string(".json")) + filtered_update),
              0)
        << mode << ": " << stderr_;
  ASSERT_EQ(
      run(path("in.ply") + " -o " + path("held.ply") + " -r 0.2 --stats " + path("held.json")), 0)
      << stderr_;
  ASSERT_EQ(run(path("in.ply") + " -o " + path("filtered-held.ply") +
                " -r 0.2 --output-normals filtered --stats " + path("filtered-held.json")),
            0)
      << stderr_;
  // A blend window closed to almost nothing keeps the filtered normals
  // nearly everywhere, on every cloud (--blend-share-high 0: the gate would
  // open the window on this one, which has no waves; and no input normals
  // kept, where nothing moved or exact, which would replace some).
  const std::string narrow =
      " -r 0.2 --blend-low 0 --blend-high 0.001 --blend-coherence 0 --blend-share-high 0"
      " --keep-input-high 0 --keep-input-exact-angle 0 --keep-input-still-angle 0"
      " --keep-input-reached-angle 0";
  ASSERT_EQ(run(path("in.ply") + " -o " + path("narrow.ply") + narrow), 0) << stderr_;
  const PointCloud d = read_point_cloud(path("default.ply")),
                   b = read_point_cloud(path("blended.ply")),
                   f = read_point_cloud(path("fitted.ply")),
                   p = read_point_cloud(path("filtered.ply")),
                   n = read_point_cloud(path("narrow.ply"));
  EXPECT_EQ(d.normals, b.normals) << "blended is the default";
  EXPECT_EQ(b.positions, p.positions);
  EXPECT_EQ(f.positions, p.positions);
  EXPECT_NE(b.normals, p.normals);
  EXPECT_NE(f.normals, p.normals);
  EXPECT_NE(n.normals, d.normals) << "--blend-low/--blend-high reach the blend";
  double worst = 0.0;
  for (Eigen::Index i = 0; i < n.normals.rows(); ++i)
    worst = std::max(worst, (n.normals.row(i) - p.normals.row(i)).norm());
  EXPECT_LT(worst, 0.01) << "a window closed to almost nothing keeps the filtered normals";
  std::ifstream stats(path("blended.json"));
  const std::string json((std::istreambuf_iterator<char>(stats)), {});
  EXPECT_NE(json.find("\"normals_not_fitted\": "), std::string::npos) << json;
  EXPECT_NE(json.find("\"normals_blended\": "), std::string::npos) << json;
  EXPECT_NE(json.find("\"input_normals_kept\": "), std::string::npos) << json;
  EXPECT_NE(json.find("\"relief_lean\": "), std::string::npos) << json;
  EXPECT_NE(json.find("\"counter_moves_limited\": "), std::string::npos) << json;
  EXPECT_NE(json.find("\"input_normals_updated\": 0,"), std::string::npos) << json;
  // The default holds the plane's exact input normals in the update, which
  // moves the positions; the filtered output holds none.
  const PointCloud h = read_point_cloud(path("held.ply")),
                   fh = read_point_cloud(path("filtered-held.ply"));
  EXPECT_NE(h.positions, b.positions);
  EXPECT_EQ(fh.positions, p.positions);
  std::ifstream held_stats(path("held.json"));
  const std::string held_json((std::istreambuf_iterator<char>(held_stats)), {});
  EXPECT_EQ(held_json.find("\"input_normals_updated\": 0,"), std::string::npos) << held_json;
  EXPECT_NE(held_json.find("\"input_normals_updated\": "), std::string::npos) << held_json;
  std::ifstream filtered_stats(path("filtered-held.json"));
  const std::string filtered_json((std::istreambuf_iterator<char>(filtered_stats)), {});
  EXPECT_NE(filtered_json.find("\"input_normals_updated\": 0,"), std::string::npos)
      << filtered_json;
}

// The number after `key` in `text` (a --stats file), -1 if key is absent.
double number_after(const std::string& text, const std::string& key) {
  const std::size_t at = text.find(key);
  if (at == std::string::npos) return -1.0;
  return std::strtod(text.c_str() + at + key.size(), nullptr);
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A plane without normals: its estimated normals face up by default (a flat
// open sheet), down with --orient=-z; an unknown side is a usage error.
TEST_F(Cli, OrientChoosesTheSideOfEstimatedNormals) {
  ASSERT_EQ(run("synth --shape plane --texture domes -n 5000 --no-normals "
                "--ground-truth-points 10 -o " +
                path("in.ply")),
            0);
  ASSERT_EQ(run(path("in.ply") + " -o " + path("up.ply") + " -r 0.05 --stats " + path("up.json")),
            0)
      << stderr_;
  ASSERT_EQ(run(path("in.ply") + " -o " + path("down.ply") + " -r 0.05 --orient=-z --stats " +
                path("down.json")),
            0)
      << stderr_;
  // The stats say the normals were estimated and how many signs orientation
  // changed: between them, the two runs turned every normal once.
  const std::string up_stats = read_text(path("up.json")),
                    down_stats = read_text(path("down.json"));
  EXPECT_NE(up_stats.find("\"normals_estimated\": true"), std::string::npos) << up_stats;
  EXPECT_EQ(number_after(up_stats, "\"normals_flipped\": ") +
                number_after(down_stats, "\"normals_flipped\": "),
            5000.0);
  EXPECT_EQ(number_after(up_stats, "\"orientation_inconsistency\": "), 0.0) << up_stats;
  ASSERT_EQ(run(path("in.ply") + " -o " + path("down2.ply") + " -r 0.05 --orient -Z"), 0)
      << stderr_;
  const PointCloud up = read_point_cloud(path("up.ply")), down = read_point_cloud(path("down.ply"));
  EXPECT_GT(up.normals.col(2).minCoeff(), 0.0);
  EXPECT_LT(down.normals.col(2).maxCoeff(), 0.0);
  EXPECT_EQ(read_point_cloud(path("down2.ply")).normals, down.normals);
  EXPECT_EQ(run(path("in.ply") + " -o " + path("x.ply") + " -r 0.05 --orient sideways"), 2);
  EXPECT_NE(stderr_.find("--orient"), std::string::npos) << stderr_;
}

TEST_F(Cli, IgnoreNormalsRunsAsOnTheSamePointsWithoutNormals) {
  PointCloud c = bumpy(true);
  for (Eigen::Index i = 0; i < c.normals.rows(); ++i)  // wrong, but oriented alike
    c.normals.row(i) = Eigen::RowVector3d(std::sin(3.0 * i), std::cos(5.0 * i), 1.5).normalized();
  write_point_cloud(path("in.ply"), c);
  PointCloud bare = c;
  bare.normals = Normals();
  write_point_cloud(path("bare.ply"), bare);
  ASSERT_EQ(run(path("bare.ply") + " -o " + path("bare_out.ply") + " -r 0.2"), 0) << stderr_;
  ASSERT_EQ(run(path("in.ply") + " -o " + path("kept.ply") + " -r 0.2"), 0) << stderr_;
  ASSERT_EQ(run(path("in.ply") + " -o " + path("ignored.ply") +
                " -r 0.2 --ignore-normals --stats " + path("ignored.json")),
            0)
      << stderr_;
  EXPECT_NE(stderr_.find("(with normals, ignored: estimating them)"), std::string::npos) << stderr_;
  const PointCloud b = read_point_cloud(path("bare_out.ply")),
                   k = read_point_cloud(path("kept.ply")),
                   g = read_point_cloud(path("ignored.ply"));
  EXPECT_EQ(g.positions, b.positions);
  EXPECT_EQ(g.normals, b.normals);
  EXPECT_NE(k.positions, b.positions) << "without the option the given normals are used";
  std::ifstream stats(path("ignored.json"));
  const std::string json((std::istreambuf_iterator<char>(stats)), {});
  EXPECT_NE(json.find("\"normals_ignored\": true"), std::string::npos) << json;
}

TEST_F(Cli, BadParametersAreUsageErrors) {
  write_point_cloud(path("in.ply"), bumpy(true));
  for (const char* args : {"--delta 2",
                           "--radius abc",
                           "--radius -1",
                           "--sigma-r 0",
                           "--update sideways",
                           "--planes 4",
                           "--threads -1",
                           "--bogus",
                           "--output-normals smooth",
                           "--fit-sigma 0",
                           "--fit-max-turn 0",
                           "--fit-range-sigma -1",
                           "--blend-high -1",
                           "--blend-low 3 --blend-high 2",
                           "--blend-low -1",
                           "--blend-low 200 --blend-high 0",
                           "--output-normals fitted --blend-high 3",
                           "--output-normals filtered --blend-low 0.5",
                           "--anchor-angle -1",
                           "--anchor-angle nan",
                           "--blend-coherence 1",
                           "--blend-coherence -0.1",
                           "--blend-isotropic-high 200",
                           "--output-normals filtered --blend-coherence 0",
                           "--wave-share-low 0.3 --wave-share-high 0.2",
                           "--wave-share-low -0.1",
                           "--wave-share-high 1.5",
                           "--wave-rest-anchor 0",
                           "--wave-rest-anchor 1.5",
                           "--wave-ceiling -1",
                           "--wave-ceiling inf",
                           "--blend-share-low 0.3 --blend-share-high 0.2",
                           "--blend-share-high 1.5",
                           "--blend-open-low 10 --blend-open-high 5",
                           "--blend-open-high 200",
                           "--fit-fine-ratio 1",
                           "--fit-fine-ratio -0.5",
                           "--fit-fine-gamma -1",
                           "--fit-range-normals both",
                           "--keep-input-high -1",
                           "--keep-input-low 0.3",
                           "--keep-input-exact-angle 90",
                           "--keep-input-exact-angle -1",
                           "--keep-input-exact-residual -0.1",
                           "--keep-input-still-angle 90",
                           "--keep-input-still-move -1",
                           "--keep-input-still-uniform 95",
                           "--keep-input-facet-neighbors -1",
                           "--keep-input-still-reach 1",
                           "--keep-input-still-reach -0.5",
                           "--counter-move-limit -1",
                           "--counter-move-lean 0",
                           "--counter-move-lean 1.5",
                           "--counter-move-engraved-share 1.5",
                           "--counter-move-engraved-share -1",
                           "--counter-move-engraved-lean 0",
                           "--counter-move-released-lean 0",
                           "--counter-move-released-lean 1.5",
                           "--tip-depth -1",
                           "--tip-slack -0.5"}) {
    EXPECT_EQ(run(path("in.ply") + " -o " + path("out.ply") + " " + args), 2) << args;
    EXPECT_FALSE(fs::exists(path("out.ply"))) << args;
  }
  EXPECT_EQ(run(path("in.ply")), 2) << "-o is required";
}

TEST_F(Cli, HelpListsEveryParameterWithItsSymbol) {
  ASSERT_EQ(run("--help"), 0);
  std::ifstream in(path("stdout.txt"));
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string help = ss.str();
  for (const char* s : {"λ", "δ", "σs", "σr", "σp", "r:", "--radius", "--lambda", "--delta",
                        "--sigma-s", "--sigma-r", "--sigma-p", "--iterations", "--isotropy",
                        "--update", "--guidance", "--no-subneighborhood", "--threads", "0.02d"})
    EXPECT_NE(help.find(s), std::string::npos) << s;
}

// Auto mode (issue 10): the texture scale is estimated, reported, and used
// for r unless -r is given; the warnings of a badly chosen r.
TEST_F(Cli, ScaleReportPrintsTheEstimateAndWritesNothing) {
  ASSERT_EQ(run("synth --shape plane --texture domes --size 0.03 --amplitude 0.01 -n 40000 "
                "--ground-truth-points 10 -o " +
                path("in.ply")),
            0);
  ASSERT_EQ(run(path("in.ply") + " --scale-report"), 0) << stderr_;
  const std::string out = read_text(path("stdout.txt"));
  const double texture = number_after(out, "texture ≈ ");
  EXPECT_GT(texture, 0.7 * 0.03) << out;
  EXPECT_LT(texture, 1.5 * 0.03) << out;
  // texture is printed to 2 digits, r to 3.
  EXPECT_NEAR(number_after(out, "→ r = "), 1.5 * texture, 0.05 * texture) << out;
  EXPECT_NE(out.find("spacing"), std::string::npos);
  EXPECT_NE(out.find("residual RMS"), std::string::npos) << "the curve behind the estimate";
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir_)) files += e.path().extension() == ".ply";
  EXPECT_EQ(files, 2u) << "only the synth files: nothing written";
}

TEST_F(Cli, ScaleReportOnTheBundledExample) {
  // Cells of radius 0.025 with both signs (examples/README.md): same-sign
  // neighbors join into larger areas, and the estimate reads 0.042.
  ASSERT_EQ(run(std::string(DETEXTURE_SOURCE_DIR) + "/examples/textured_cube.ply --scale-report"),
            0)
      << stderr_;
  const std::string out = read_text(path("stdout.txt"));
  const double texture = number_after(out, "texture ≈ ");
  EXPECT_GT(texture, 0.7 * 0.025) << out;
  EXPECT_LT(texture, 2.0 * 0.025) << out;
  EXPECT_NE(out.find("100000 points"), std::string::npos) << out;
}

TEST_F(Cli, AutoRadiusIsTheDefaultAndAnExplicitRadiusWins) {
  // 20000 points (spacing 0.007) resolve domes of radius 0.03 as 40000 do,
  // at a third of the time (each r-ball holds about 140 points).
  ASSERT_EQ(run("synth --shape plane --texture domes --size 0.03 --amplitude 0.01 -n 20000 "
                "--ground-truth-points 10 -o " +
                path("in.ply")),
            0);
  ASSERT_EQ(run(path("in.ply") + " -o " + path("out.ply") + " --stats " + path("s.json")), 0)
      << stderr_;
  EXPECT_NE(stderr_.find("× texture radius"), std::string::npos) << stderr_;
  std::string stats = read_text(path("s.json"));
  EXPECT_NE(stats.find("\"radius_choice\": \"texture\""), std::string::npos) << stats;
  EXPECT_NE(stats.find("\"texture_found\": true"), std::string::npos) << stats;
  const double texture = number_after(stats, "\"texture_radius\": ");
  EXPECT_NEAR(number_after(stats, "\"radius\": "), 1.5 * texture, 1e-5) << stats;
  ASSERT_EQ(
      run(path("in.ply") + " -o " + path("out.ply") + " -f -r 0.02 --stats " + path("s.json")), 0)
      << stderr_;
  stats = read_text(path("s.json"));
  EXPECT_NE(stats.find("\"radius_choice\": \"given\""), std::string::npos) << stats;
  EXPECT_DOUBLE_EQ(number_after(stats, "\"radius\": "), 0.02);
  EXPECT_EQ(stats.find("\"scale\""), std::string::npos) << "no estimate when r is given";
}

TEST_F(Cli, NoTextureIsSaidAndTheFallbackRadiusUsed) {
  ASSERT_EQ(run("synth --shape plane --texture none -n 20000 --ground-truth-points 10 -o " +
                path("in.ply")),
            0);
  ASSERT_EQ(run(path("in.ply") + " -o " + path("out.ply") + " --stats " + path("s.json")), 0)
      << stderr_;
  EXPECT_NE(stderr_.find("warning: no texture found"), std::string::npos) << stderr_;
  EXPECT_NE(stderr_.find("has no texture to remove"), std::string::npos) << stderr_;
  const std::string stats = read_text(path("s.json"));
  EXPECT_NE(stats.find("\"radius_choice\": \"fallback\""), std::string::npos) << stats;
  // The plane's diagonal is √2: the fallback 0.02 d = 0.0283 holds more than
  // 30 neighbors at 20000 points per unit area (π 0.0283² 20000 = 50).
  EXPECT_NEAR(number_after(stats, "\"radius\": "), 0.02 * std::sqrt(2.0), 1e-4) << stats;
  // Too sparse for the analysis (the 7-neighbor case): the 41 x 41
  // grid of spacing 0.025 falls back to the radius holding about 30
  // neighbors, 0.025 √(30/π) = 0.077 (the estimated spacing is 0.991 of the
  // grid's), not 0.02 d = 0.028 with its 5 neighbors.
  write_point_cloud(path("grid.ply"), bumpy(true));
  ASSERT_EQ(run(path("grid.ply") + " -o " + path("grid.out.ply") + " --stats " + path("g.json")), 0)
      << stderr_;
  const std::string grid = read_text(path("g.json"));
  EXPECT_NEAR(number_after(grid, "\"radius\": "), 0.991 * 0.025 * std::sqrt(30.0 / M_PI), 1e-3)
      << grid;
  EXPECT_GT(number_after(grid, "\"neighbors_mean\": "), 25.0) << grid;
  EXPECT_EQ(stderr_.find("neighbors per point on average"), std::string::npos) << stderr_;
}

TEST_F(Cli, WarnsWhenTheRadiusHoldsTooFewNeighbors) {
  // The 41 x 41 grid has spacing 0.025: within r = 0.03 a point has itself
  // and its 4 nearest (fewer on the border); 30 neighbors need
  // π r² / 0.025² = 30, r = 0.077.
  write_point_cloud(path("in.ply"), bumpy(true));
  ASSERT_EQ(run(path("in.ply") + " -o " + path("out.ply") + " -r 0.03"), 0) << stderr_;
  EXPECT_NE(stderr_.find("neighbors per point on average"), std::string::npos) << stderr_;
  const std::size_t at = stderr_.find("; r = ");
  ASSERT_NE(at, std::string::npos) << stderr_;
  const double r30 = std::strtod(stderr_.c_str() + at + 6, nullptr);
  EXPECT_GT(r30, 0.065) << stderr_;
  EXPECT_LT(r30, 0.085) << stderr_;
  ASSERT_EQ(run(path("in.ply") + " -o " + path("out2.ply") + " -r 0.1"), 0) << stderr_;
  EXPECT_EQ(stderr_.find("neighbors per point on average"), std::string::npos)
      << "50 neighbors: no warning";
}

TEST_F(Cli, RefusesAHugeRadiusUnlessForced) {
  // r = 0.6 on the unit square: every neighborhood holds most of the cloud.
  write_point_cloud(path("in.ply"), bumpy(true));
  EXPECT_EQ(run(path("in.ply") + " -o " + path("out.ply") + " -r 0.6"), 2);
  const std::size_t error = stderr_.find("detexture: error: r = 0.6 would put about");
  ASSERT_NE(error, std::string::npos) << stderr_;
  EXPECT_EQ(lines(stderr_.substr(error)), 1) << "a one-line error, last: " << stderr_;
  EXPECT_NE(stderr_.find("% of the cloud"), std::string::npos) << stderr_;
  EXPECT_NE(stderr_.find("--force"), std::string::npos) << stderr_;
  EXPECT_FALSE(fs::exists(path("out.ply")));
  EXPECT_EQ(run(path("in.ply") + " -o " + path("out.ply") + " -r 0.6 --force -q"), 0) << stderr_;
  EXPECT_TRUE(fs::exists(path("out.ply")));
  EXPECT_EQ(run(path("in.ply") + " -o " + path("capped.ply") + " -r 0.6 --max-neighbors 64 -q"), 0)
      << "64 nearest kept: the neighborhoods stay small; " << stderr_;
}

// detexture render: a picture whose content is what was asked for, and the
// exit codes of each kind of failure.
TEST_F(Cli, RenderDrawsCloudsSideBySide) {
  PointCloud plane = bumpy(true);
  std::vector<double> height(plane.size());
  for (std::size_t i = 0; i < plane.size(); ++i) height[i] = plane.positions(i, 2);
  plane.extras.push_back({"texture_height", ScalarType::Float32, height});
  write_point_cloud(path("a.ply"), plane);
  write_point_cloud(path("b.xyz"), bumpy(false));  // no normals: estimated
  ASSERT_EQ(run("render " + path("a.ply") + " " + path("b.xyz") + " -o " + path("ab.png") +
                " --size 400x200 --view top --light 0,0 --no-labels --color-by texture_height"),
            0)
      << stderr_;
  EXPECT_NE(stderr_.find("b.xyz has no property 'texture_height'"), std::string::npos) << stderr_;
  const Image image = test::read_png(path("ab.png"));
  ASSERT_EQ(image.width, 400);
  ASSERT_EQ(image.height, 200);
  // Left panel, under a headlight: the bump's top is the highest value, viridis' yellow end;
  // the flat border near its dark end. Right panel: plain surface colour.
  const std::array<std::uint8_t, 3> white = {255, 255, 255};
  EXPECT_EQ(image.pixel(3, 3), white);
  int yellow = 0, coloured_right = 0, plain_right = 0;
  for (int y = 0; y < 200; ++y)
    for (int x = 0; x < 400; ++x) {
      const auto c = image.pixel(x, y);
      if (x < 150) yellow += c[0] > 200 && c[1] > 180 && c[2] < 100;
      if (x >= 200 && x < 330 && c != white) {
        plain_right += c[0] == c[1];  // grey, from the surface colour
        coloured_right += c[0] != c[1];
      }
    }
  EXPECT_GT(yellow, 10);
  EXPECT_GT(plain_right, 5000);
  EXPECT_EQ(coloured_right, 0);
}

TEST_F(Cli, RenderDrawsTheFacesOfAMesh) {
  // A unit square of two triangles, written as a PLY mesh without normals.
  PointCloud mesh;
  mesh.positions.resize(4, 3);
  mesh.positions << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  OtherElement faces;
  faces.name = "face";
  faces.properties = {{"vertex_indices", ScalarType::Int32, true, ScalarType::UInt8}};
  faces.values = {3, 0, 1, 2, 3, 0, 2, 3};
  faces.row_offsets = {0, 4, 8};
  mesh.other_elements.push_back(faces);
  write_point_cloud(path("mesh.ply"), mesh);
  ASSERT_EQ(run("render " + path("mesh.ply") + " -o " + path("mesh.png") +
                " --size 200x200 --view top --light 0,0 --no-labels"),
            0)
      << stderr_;
  const Image image = test::read_png(path("mesh.png"));
  ASSERT_EQ(image.width, 200);
  // The default 12 px margins: pixel centres 12.5 .. 187.5 lie in the
  // square [12, 188], all in the surface colour (face normals, facing the
  // light); four corner points alone would be four dots.
  const RenderParams defaults;
  for (int y = 0; y < 200; ++y)
    for (int x = 0; x < 200; ++x) {
      const bool inside = x >= 12 && x < 188 && y >= 12 && y < 188;
      const std::array<std::uint8_t, 3> want =
          inside ? defaults.surface_color : defaults.background;
      ASSERT_EQ(image.pixel(x, y), want) << x << "," << y;
    }
}

TEST_F(Cli, RenderExitCodes) {
  write_point_cloud(path("in.ply"), bumpy(true));
  EXPECT_EQ(run("render " + path("missing.ply") + " -o " + path("o.png")), 3);
  EXPECT_EQ(lines(stderr_), 1) << stderr_;
  EXPECT_NE(stderr_.find("missing.ply"), std::string::npos);
  EXPECT_FALSE(fs::exists(path("o.png")));
  for (const char* args : {"--bogus", "--view sideways", "--size 12", "--range 1",
                           "--point-size -1", "--width 5", "--up w", "--label a --label b"}) {
    EXPECT_EQ(run("render " + path("in.ply") + " -o " + path("o.png") + " " + args), 2) << args;
    EXPECT_FALSE(fs::exists(path("o.png"))) << args;
  }
  EXPECT_EQ(run("render " + path("in.ply")), 2) << "-o is required";
  EXPECT_EQ(run("render " + path("in.ply") + " -o " + path("o.jpg")), 2) << "PNG only";
  EXPECT_EQ(run("render " + path("in.ply") + " -o " + path("o.png") + " --color-by nothing"), 3);
  write_text("taken.png", "keep me");
  EXPECT_EQ(run("render " + path("in.ply") + " -o " + path("taken.png")), 4);
  EXPECT_NE(stderr_.find("--force"), std::string::npos);
  EXPECT_EQ(fs::file_size(path("taken.png")), 7u);
  EXPECT_EQ(run("render " + path("in.ply") + " -o " + path("taken.png") + " -f -q"), 0) << stderr_;
  EXPECT_EQ(stderr_, "");
  EXPECT_EQ(test::read_png(path("taken.png")).width, RenderParams().width);
  EXPECT_EQ(run("render " + path("in.ply") + " -o " + path("no/such/dir.png")), 4);
}

}  // namespace
}  // namespace detexture
