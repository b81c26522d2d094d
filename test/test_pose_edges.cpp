// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Pose refinement without depth (computeEdgeMaps, refinePoseEdges).

#include "test_precomp.hpp"
#include "test_pose_common.hpp"
#include "../src/pose_refine.hpp"

namespace opencv_test {
namespace {

using namespace pose_test;

/** The rendered ape at (R, t) pasted onto a real LM-O frame (shipped), whose clutter gives the
edge maps plenty of wrong edges. */
static Mat pasteOnRealFrame(MeshRenderer& mr, const Matx33d& R, const Vec3d& t, const Matx33d& K)
{
    Mat scene = imread(cvtest::findDataFile("lmo_mini/test/000002/rgb/000902.png"), IMREAD_COLOR);
    CV_Assert(!scene.empty());
    Mat color, mask;
    mr.renderer->render(mr.handle, R, t, K, color, noArray(), mask);
    color.copyTo(scene, mask);
    return scene;
}

struct EdgeTrial
{
    double before, after; // 2D projection error (px) of the start and of the refined pose
    EdgeRefineResult res;
};

/** A random view of the ape (templates' range: elevation 10-60 degrees, 600-900 mm, any in-plane
angle, off the image centre) pasted on a real frame; the start turned by `deg` about a random axis
through the centre and moved 10 mm; refined with `params`, the object drawn by mr's renderer or by
`drawer`. */
static EdgeTrial runEdgeTrial(MeshRenderer& mr, RNG& rng, double deg,
                              const EdgeRefineParams& params = EdgeRefineParams(),
                              const cv::forestmod::detail::ObjectDrawer* drawer = 0)
{
    const Matx33d K = lmoIntrinsics();
    const Vec3d c(mr.mesh.center().x, mr.mesh.center().y, mr.mesh.center().z);
    Matx33d R_gt;
    Vec3d t_gt;
    const double el = rng.uniform(10.0, 60.0) * CV_PI / 180, az = rng.uniform(0.0, 2 * CV_PI);
    ViewSampler::lookAt(mr.mesh.center(),
                        Vec3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                              std::sin(el)),
                        rng.uniform(600.0, 900.0), rng.uniform(-180.0, 180.0), R_gt, t_gt);
    t_gt += Vec3d(rng.uniform(-150.0, 150.0), rng.uniform(-100.0, 100.0), 0);
    const Mat scene = pasteOnRealFrame(mr, R_gt, t_gt, K);
    EdgeMaps maps;
    computeEdgeMaps(scene, maps, params);
    const Vec3d pc = R_gt * c + t_gt;
    const Matx33d dR = randomRotation(rng, deg * CV_PI / 180);
    Vec3d dt(rng.gaussian(1), rng.gaussian(1), rng.gaussian(1));
    dt *= 10.0 / cv::norm(dt);
    const Matx33d R0 = dR * R_gt;
    const Vec3d t0 = dR * (t_gt - pc) + pc + dt;
    EdgeTrial tr;
    tr.before = projectionError2D(mr.mesh.vertices, K, R0, t0, R_gt, t_gt);
    tr.res = drawer ? cv::forestmod::detail::refinePoseEdges(*drawer, maps, K, R0, t0, params)
                    : refinePoseEdges(*mr.renderer, mr.handle, maps, K, R0, t0, params);
    tr.after = projectionError2D(mr.mesh.vertices, K, tr.res.R, tr.res.t, R_gt, t_gt);
    return tr;
}

TEST(Forestmod_PoseEdges, refinement_recovers_pose_on_rendered_object_over_real_clutter)
{
    MeshRenderer mr(apeMesh(), Size(640, 480));
    RNG rng(20261122);
    const int trials = 20;
    int good = 0, far_start = 0;
    for (int i = 0; i < trials; ++i)
    {
        // the start 10 degrees off: a template match's error (views ~16 degrees apart)
        const EdgeTrial tr = runEdgeTrial(mr, rng, 10.0);
        far_start += tr.before >= 4.0;
        good += tr.after < 2.0;
        EXPECT_GT(tr.res.points, 20);
        EXPECT_GE(tr.res.inlier_ratio, 0.0);
        EXPECT_LE(tr.res.inlier_ratio, 1.0);
        std::cout << "[ INFO    ] trial " << i << ": 2D projection error " << tr.before << " -> "
                  << tr.after << " px, inliers " << tr.res.inlier_ratio << ", "
                  << tr.res.iterations << " iterations" << std::endl;
    }
    // the starts are as far off as a template match (most >= 4 px); the refinement brings most
    // of them under 2 px (the silhouette is exact here; measured 18/20, doc/pose.md; the others
    // stop in a local minimum of the clutter's edges, 7-10 px away)
    EXPECT_GE(far_start, 14);
    EXPECT_GE(good, 16);
}

// The detector refines with the coarse mesh drawn on the CPU (coarseMesh, drawMesh: no lock, the
// hypotheses in parallel): as accurate as the OSMesa rendering of the full mesh, same trials.
TEST(Forestmod_PoseEdges, refinement_with_the_cpu_drawing_of_the_coarse_mesh)
{
    CoarseApe ape;
    MeshRenderer& mr = ape.mr;
    RNG rng_renderer(20261122), rng_drawn(20261122), rng_outline(20261122);
    const int trials = 20;
    int good_renderer = 0, good_drawn = 0, good_outline = 0;
    for (int i = 0; i < trials; ++i)
    {
        const EdgeTrial a = runEdgeTrial(mr, rng_renderer, 10.0);
        const EdgeTrial b = runEdgeTrial(mr, rng_drawn, 10.0, EdgeRefineParams(), &ape.drawer);
        const EdgeTrial c = runEdgeTrial(mr, rng_outline, 10.0, EdgeRefineParams(),
                                         &ape.outline_drawer);
        ASSERT_EQ(a.before, b.before) << i; // the same start
        ASSERT_EQ(a.before, c.before) << i;
        EXPECT_GT(b.res.points, 20) << i;
        EXPECT_GT(c.res.points, 20) << i;
        good_renderer += a.after < 2.0;
        good_drawn += b.after < 2.0;
        good_outline += c.after < 2.0;
        std::cout << "[ INFO    ] trial " << i << ": " << a.before << " px -> " << a.after
                  << " (renderer), " << b.after << " (drawn), " << c.after << " (outline)"
                  << std::endl;
    }
    EXPECT_GE(good_drawn, 16);
    EXPECT_GE(good_drawn, good_renderer - 1);
    EXPECT_GE(good_outline, 16);
    EXPECT_GE(good_outline, good_renderer - 1);
}

// The variant table of doc/pose.md ("Refinement without depth"):
//   ./bin/opencv_test_forestmod --gtest_filter='*edge_refinement_variants' --gtest_also_run_disabled_tests
TEST(Forestmod_PoseEdges, DISABLED_edge_refinement_variants)
{
    MeshRenderer mr(apeMesh(), Size(640, 480));
    std::vector<std::pair<std::string, EdgeRefineParams> > variants;
    EdgeRefineParams p;
    variants.push_back(std::make_pair(std::string("defaults (no grid search)"), p));
    p.search_angle = 12;
    variants.push_back(std::make_pair(std::string("grid search 12 degrees"), p));
    p = EdgeRefineParams();
    p.orientations = 8;
    variants.push_back(std::make_pair(std::string("8 bins"), p));
    p.search_angle = 12;
    variants.push_back(std::make_pair(std::string("8 bins, grid search"), p));
    p = EdgeRefineParams();
    p.inner_edges = true;
    variants.push_back(std::make_pair(std::string("inner edges"), p));
    for (size_t v = 0; v < variants.size(); ++v)
        for (int deg = 8; deg <= 10; deg += 2)
        {
            RNG rng(20261122);
            int good = 0;
            const int trials = 20;
            for (int i = 0; i < trials; ++i)
                good += runEdgeTrial(mr, rng, deg, variants[v].second).after < 2.0;
            std::cout << "[ INFO    ] " << variants[v].first << ", start " << deg << " deg: " << good
                      << " / " << trials << " under 2 px" << std::endl;
            EXPECT_GE(good, 0);
        }
}

/** ../shared/data/lmo (FORESTMOD_SHARED_DATA); the test is skipped without it. */
static std::string sharedLmoRoot()
{
    const std::string shared = sharedDataPath();
    if (shared.empty())
        throw SkipTestException("FORESTMOD_SHARED_DATA does not point to ../shared/data");
    return shared + "/lmo";
}

// The real-frame numbers of doc/pose.md: the demo's ape model (scripts/demo.sh's sampler) on the
// 50 LM-O frames of ../shared (FORESTMOD_SHARED_DATA), RGB only:
//   ./bin/opencv_test_forestmod --gtest_filter='*edge_refinement_on_real_frames' --gtest_also_run_disabled_tests
TEST(Forestmod_PoseEdges, DISABLED_edge_refinement_on_real_frames)
{
    const std::string root = sharedLmoRoot();
    const BopDataset ds = BopDataset::open(root);
    const Mesh ape = Mesh::load(root + "/models/obj_000001.ply");
    ViewSampler::Params sp;
    sp.level = 2;
    sp.min_elevation = 0;
    sp.max_elevation = 60;
    sp.radii.clear();
    sp.radii.push_back(700);
    sp.radii.push_back(850);
    sp.inplane_min = -180;
    sp.inplane_max = 160;
    sp.inplane_step = 20;
    Ptr<cv::forestmod::Detector> det = getDefaultForestLINE();
    DetectorParams dp = det->getParams();
    dp.forest.fuzzy_margin = 0.5f;
    det->setParams(dp);
    ASSERT_GT(det->addTemplates(ape, "obj_000001", ViewSampler(sp), lmoIntrinsics(), Size(640, 480)), 1000);
    det->train();
    Ptr<Renderer> renderer = Renderer::create(Size(640, 480));
    const int handle = renderer->addMesh(ape);
    EdgeRefineParams inner;
    inner.inner_edges = true;
    int found = 0, near_start = 0, good = 0, good_near = 0, good_inner = 0, found_detect = 0,
        good_detect = 0;
    const std::vector<Frame> frames = ds.frames(2);
    for (size_t f = 0; f < frames.size(); ++f)
        for (size_t g = 0; g < frames[f].gt.size(); ++g)
        {
            const GroundTruth& gt = frames[f].gt[g];
            if (gt.obj_id != 1)
                continue;
            const Mat img = frames[f].rgb();
            std::vector<Mat> src(det->getModalities().size(), img);
            // detect() as a user calls it: the pose chosen among the detection's hypotheses
            // (PoseParams::rgb_hypotheses), refined by edge alignment
            std::vector<PoseMatch> dm;
            det->detect(src, frames[f].K, 80, dm);
            if (!dm.empty() && dm[0].has_pose
                && boxIoU(Rect2d(dm[0].x, dm[0].y, dm[0].pose.box.width, dm[0].pose.box.height),
                          Rect2d(gt.bbox_obj)) >= 0.5)
            {
                ++found_detect;
                good_detect += projectionError2D(ape.vertices, frames[f].K, dm[0].R, dm[0].t,
                                                 gt.R, gt.t) < 5;
            }
            std::vector<PoseMatch> ms;
            PoseParams pp;
            pp.rgb_refine = false;
            det->detect(src, frames[f].K, 80, ms, std::vector<String>(), pp);
            if (ms.empty() || !ms[0].has_pose
                || boxIoU(Rect2d(ms[0].x, ms[0].y, ms[0].pose.box.width, ms[0].pose.box.height),
                          Rect2d(gt.bbox_obj)) < 0.5)
                continue;
            ++found;
            const double e0 = projectionError2D(ape.vertices, frames[f].K, ms[0].R, ms[0].t,
                                                gt.R, gt.t);
            EdgeMaps maps;
            computeEdgeMaps(img, maps);
            const EdgeRefineResult r = refinePoseEdges(*renderer, handle, maps, frames[f].K,
                                                       ms[0].R, ms[0].t);
            const double e1 = projectionError2D(ape.vertices, frames[f].K, r.R, r.t, gt.R, gt.t);
            EdgeMaps maps_inner;
            computeEdgeMaps(img, maps_inner, inner);
            const EdgeRefineResult ri = refinePoseEdges(*renderer, handle, maps_inner,
                                                        frames[f].K, ms[0].R, ms[0].t, inner);
            const double e2 = projectionError2D(ape.vertices, frames[f].K, ri.R, ri.t, gt.R,
                                                gt.t);
            near_start += e0 < 15;
            good += e1 < 5;
            good_near += e0 < 15 && e1 < 5;
            good_inner += e2 < 5;
            std::cout << "[ INFO    ] frame " << frames[f].im_id << ": " << e0 << " -> " << e1
                      << " px (inner edges: " << e2 << " px)" << std::endl;
        }
    std::cout << "[ INFO    ] top match found (box IoU >= 0.5) in " << found << " frames; " << near_start
              << " start within 15 px, " << good_near << " of them end under 5 px; all found: "
              << good << " under 5 px (" << good_inner << " with inner edges)" << std::endl;
    std::cout << "[ INFO    ] detect() with " << PoseParams().rgb_hypotheses << " hypotheses per "
              << "detection: found in " << found_detect << " frames, " << good_detect
              << " under 5 px" << std::endl;
    EXPECT_GT(found, 0);
}

/** Drift of the refinement started at the ground truth of one object instance: the projection
error of the end pose and the shift of the object's centre in the image (end - truth, pixels). */
struct TruthDrift
{
    double error, du, dv;
};

static TruthDrift refineFromTruth(Renderer& renderer, int handle, const EdgeMaps& maps,
                                  const Matx33d& K, const GroundTruth& gt,
                                  const std::vector<Point3f>& pts)
{
    const EdgeRefineResult r = refinePoseEdges(renderer, handle, maps, K, gt.R, gt.t);
    const Vec3d a = K * gt.t, b = K * r.t;
    TruthDrift d;
    d.error = projectionError2D(pts, K, r.R, r.t, gt.R, gt.t);
    d.du = b[0] / b[2] - a[0] / a[2];
    d.dv = b[1] / b[2] - a[1] / a[2];
    return d;
}

// The objects of LM-O frames rendered at their ground truth: each mesh loaded and uploaded once,
// and a frame's image with every object's rendering pasted over it (exact silhouettes, the real
// clutter around them).
struct PastedObjects
{
    explicit PastedObjects(const std::string& root_)
        : root(root_), renderer(Renderer::create(Size(640, 480)))
    {
    }
    /** The frame's image with the renderings pasted; loads the meshes it meets first. */
    Mat paste(const Frame& frame)
    {
        Mat scene = frame.rgb();
        for (size_t g = 0; g < frame.gt.size(); ++g)
        {
            const GroundTruth& gt = frame.gt[g];
            if (!handle.count(gt.obj_id))
            {
                mesh[gt.obj_id] = Mesh::load(cv::format("%s/models/obj_%06d.ply", root.c_str(),
                                                        gt.obj_id));
                handle[gt.obj_id] = renderer->addMesh(mesh[gt.obj_id]);
            }
            Mat color, mask;
            renderer->render(handle[gt.obj_id], gt.R, gt.t, frame.K, color, noArray(), mask);
            color.copyTo(scene, mask);
        }
        return scene;
    }
    std::string root;
    Ptr<Renderer> renderer;
    std::map<int, int> handle;
    std::map<int, Mesh> mesh;
};

// Where the refinement's optimum lies on real frames: started at the ground truth of every
// instance at least half visible in frames 15-49 of LM-O scene 2 (frames no reported table
// uses), on the real image and on the same image with the objects' renderings pasted at the
// truth (exact silhouettes, real clutter around them). Prints, per object, the end's projection
// error and the mean shift of its centre. Measurement, not run by default (doc/pose.md), with
// FORESTMOD_SHARED_DATA set and --gtest_also_run_disabled_tests:
//   ./bin/opencv_test_forestmod --gtest_filter='*refinement_from_the_ground_truth*'
TEST(Forestmod_PoseEdges, DISABLED_refinement_from_the_ground_truth_on_real_frames)
{
    const std::string root = sharedLmoRoot();
    const BopDataset ds = BopDataset::open(root);
    const std::vector<Frame> frames = ds.frames(2);
    ASSERT_GE(frames.size(), (size_t)50);
    PastedObjects objects(root);
    std::map<int, std::vector<TruthDrift> > real, pasted;
    for (size_t f = 15; f < 50; ++f)
    {
        const Mat scene = objects.paste(frames[f]);
        EdgeMaps img_maps, scene_maps; // once per frame, for all its instances
        computeEdgeMaps(frames[f].rgb(), img_maps);
        computeEdgeMaps(scene, scene_maps);
        for (size_t g = 0; g < frames[f].gt.size(); ++g)
        {
            const GroundTruth& gt = frames[f].gt[g];
            if (gt.visib_fract >= 0 && gt.visib_fract < 0.5) // unknown: every instance
                continue;
            const int handle = objects.handle[gt.obj_id];
            const std::vector<Point3f>& pts = objects.mesh[gt.obj_id].vertices;
            real[gt.obj_id].push_back(refineFromTruth(*objects.renderer, handle, img_maps,
                                                      frames[f].K, gt, pts));
            pasted[gt.obj_id].push_back(refineFromTruth(*objects.renderer, handle, scene_maps,
                                                        frames[f].K, gt, pts));
        }
    }
    int n = 0, real5 = 0, pasted5 = 0;
    for (std::map<int, std::vector<TruthDrift> >::const_iterator it = real.begin();
         it != real.end(); ++it)
    {
        const std::vector<TruthDrift>& r = it->second;
        const std::vector<TruthDrift>& p = pasted[it->first];
        std::vector<double> er, ep;
        double du = 0, dv = 0;
        int r5 = 0, p5 = 0;
        for (size_t i = 0; i < r.size(); ++i)
        {
            er.push_back(r[i].error);
            ep.push_back(p[i].error);
            du += r[i].du / r.size();
            dv += r[i].dv / r.size();
            r5 += r[i].error < 5;
            p5 += p[i].error < 5;
        }
        std::sort(er.begin(), er.end());
        std::sort(ep.begin(), ep.end());
        std::cout << cv::format("[ INFO    ] object %2d, %2d instances: real frames median %.2f px, "
                                "%2d under 5 px, mean centre shift (%.2f, %.2f) px; pasted "
                                "renderings median %.2f px, %2d under 5 px",
                                it->first, (int)r.size(), er[er.size() / 2], r5, du, dv,
                                ep[ep.size() / 2], p5)
                  << std::endl;
        n += (int)r.size();
        real5 += r5;
        pasted5 += p5;
    }
    std::cout << "[ INFO    ] " << n << " instances: " << real5 << " (real) and " << pasted5
              << " (pasted) end under 5 px" << std::endl;
    // on exact silhouettes the truth stays (nearly) a fixed point among real clutter
    ASSERT_GT(n, 100);
    EXPECT_GE(pasted5, 0.9 * n);
}

// The detector's two ways to the edge alignment's points, side by side on real frames: the coarse
// mesh drawn (the mask's boundary) or its silhouette edges (the outline, the detector's way),
// started at the ground truth and at the truth turned 10 degrees about a random axis and moved
// 10 mm, on the real images of frames 15-49 of LM-O scene 2 (every instance; those at least half
// visible when the scene has scene_gt_info.json) and on the same images with the objects'
// renderings pasted at the truth. Prints the instances ending under 5 px, the median and lower
// quartile of the projection error, and the time per refinement. Measurement, not run by default
// (doc/pose.md, "Drawing at detection time"), with FORESTMOD_SHARED_DATA set and
// --gtest_also_run_disabled_tests:
//   ./bin/opencv_test_forestmod --gtest_filter='*outline_and_drawn_mask_on_real_frames*'
TEST(Forestmod_PoseEdges, DISABLED_outline_and_drawn_mask_on_real_frames)
{
    namespace fd = cv::forestmod::detail;
    const std::string root = sharedLmoRoot();
    const BopDataset ds = BopDataset::open(root);
    const std::vector<Frame> frames = ds.frames(2);
    ASSERT_GE(frames.size(), (size_t)50);
    PastedObjects objects(root);
    std::map<int, int> winding;
    std::map<int, Mesh> coarse;
    std::map<int, fd::SilhouetteEdges> edges;
    RNG rng(20261126);
    // [scene: real, pasted][points: mask, outline][start: truth, turned]
    std::vector<double> err[2][2][2];
    int add[2][2][2] = {}; // ADD (ADI for LINEMOD's symmetric objects) < 0.1 diameter
    double seconds[2] = { 0, 0 };
    for (size_t f = 15; f < 50; ++f)
    {
        const Mat img = frames[f].rgb();
        EdgeMaps maps[2];
        computeEdgeMaps(img, maps[0]);
        computeEdgeMaps(objects.paste(frames[f]), maps[1]);
        for (size_t g = 0; g < frames[f].gt.size(); ++g)
        {
            const GroundTruth& gt = frames[f].gt[g];
            if (gt.visib_fract >= 0 && gt.visib_fract < 0.5)
                continue;
            const Mesh& mesh = objects.mesh[gt.obj_id];
            if (!coarse.count(gt.obj_id)) // the detector's copy, its clusters' order, its edges
            {
                Mesh& c = coarse[gt.obj_id];
                c = fd::coarseMesh(mesh, fd::drawingCell(mesh.diameter()));
                winding[gt.obj_id] = fd::closedWinding(c);
                fd::clusterFaces(c, winding[gt.obj_id]);
                edges[gt.obj_id] = fd::silhouetteEdges(c, winding[gt.obj_id]);
            }
            Vec3d axis(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0));
            Vec3d shift(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0));
            Matx33d turn;
            Rodrigues(axis * (10 * CV_PI / 180 / cv::norm(axis)), turn);
            const Matx33d R0[2] = { gt.R, turn * gt.R };
            const Vec3d t0[2] = { gt.t, gt.t + shift * (10.0 / cv::norm(shift)) };
            const Mesh& c = coarse[gt.obj_id];
            const fd::MeshDrawer drawer[2] = {
                fd::MeshDrawer(c, winding[gt.obj_id], img.size()),
                fd::MeshDrawer(c, winding[gt.obj_id], img.size(), 0, 0, &edges[gt.obj_id])
            };
            for (int sc = 0; sc < 2; ++sc)
                for (int way = 0; way < 2; ++way)
                    for (int start = 0; start < 2; ++start)
                    {
                        const int64 t_begin = getTickCount();
                        const EdgeRefineResult r = fd::refinePoseEdges(
                            drawer[way], maps[sc], frames[f].K, R0[start], t0[start],
                            EdgeRefineParams());
                        seconds[way] += (getTickCount() - t_begin) / getTickFrequency();
                        err[sc][way][start].push_back(projectionError2D(
                            mesh.vertices, frames[f].K, r.R, r.t, gt.R, gt.t));
                        const bool symmetric = gt.obj_id == 10 || gt.obj_id == 11;
                        const double e3 = symmetric
                            ? adiError(mesh.vertices, r.R, r.t, gt.R, gt.t)
                            : addError(mesh.vertices, r.R, r.t, gt.R, gt.t);
                        add[sc][way][start] += e3 < 0.1 * mesh.diameter();
                    }
        }
    }
    const size_t n = err[0][0][0].size();
    ASSERT_GT(n, 100u);
    const char* scenes[2] = { "real", "pasted" };
    const char* ways[2] = { "drawn mask", "outline" };
    const char* starts[2] = { "truth", "turned" };
    int under[2][2][2];
    for (int sc = 0; sc < 2; ++sc)
        for (int way = 0; way < 2; ++way)
            for (int start = 0; start < 2; ++start)
            {
                std::vector<double> e = err[sc][way][start];
                std::sort(e.begin(), e.end());
                under[sc][way][start] = (int)(std::lower_bound(e.begin(), e.end(), 5.0)
                                              - e.begin());
                std::cout << cv::format("[ INFO    ] %s frames, %s, from the %s: %d / %d under "
                                        "5 px, median %.2f px, lower quartile %.2f px; ADD/ADI "
                                        "< 0.1 d %d",
                                        scenes[sc], ways[way], starts[start],
                                        under[sc][way][start], (int)n, e[n / 2], e[n / 4],
                                        add[sc][way][start])
                          << std::endl;
            }
    std::cout << cv::format("[ INFO    ] %.2f ms per refinement with the drawn mask, %.2f with "
                            "the outline (1 thread)", seconds[0] * 1000 / (4 * n),
                            seconds[1] * 1000 / (4 * n))
              << std::endl;
    // on exact silhouettes the outline keeps the truth as the drawn mask does
    EXPECT_GE(under[1][1][0], under[1][0][0] - 0.02 * n);
}

TEST(Forestmod_PoseEdges, true_pose_is_a_fixed_point)
{
    const Matx33d K = lmoIntrinsics();
    MeshRenderer mr(apeMesh(), Size(640, 480));
    Matx33d R;
    Vec3d t;
    ViewSampler::lookAt(mr.mesh.center(), Vec3d(0.5, 0.5, 0.7071), 750, 30, R, t);
    const Mat scene = pasteOnRealFrame(mr, R, t, K);
    EdgeMaps maps;
    computeEdgeMaps(scene, maps);
    const EdgeRefineResult res = refinePoseEdges(*mr.renderer, mr.handle, maps, K, R, t);
    EXPECT_LT(projectionError2D(mr.mesh.vertices, K, res.R, res.t, R, t), 1.0);
    EXPECT_GT(res.inlier_ratio, 0.9);
    // the same object 30 px off: few of its silhouette points lie on edges
    const EdgeRefineResult off = refinePoseEdges(*mr.renderer, mr.handle, maps, K, R,
                                                 t + Vec3d(30.0 * t[2] / K(0, 0), 0, 0),
                                                 [] {
                                                     EdgeRefineParams p;
                                                     p.passes = 1;
                                                     p.iterations = 1;
                                                     p.search_angle = 0;
                                                     return p;
                                                 }());
    EXPECT_LT(off.inlier_ratio, res.inlier_ratio - 0.3);
}

TEST(Forestmod_PoseEdges, edge_maps_measure_distance_to_edges_of_the_same_orientation)
{
    // a vertical step edge at x = 40: its gradient is horizontal (bin 0)
    Mat img(80, 80, CV_8UC1, Scalar(0));
    img.colRange(40, 80).setTo(200);
    EdgeMaps maps;
    computeEdgeMaps(img, maps);
    const int bins = EdgeRefineParams().orientations;
    ASSERT_EQ((size_t)bins, maps.distance.size());
    ASSERT_EQ(CV_32FC1, maps.distance[0].type());
    EXPECT_GT(countNonZero(maps.edges), 60);
    // bin 0 (horizontal gradient): distance grows with |x - edge| up to the truncation
    const float d5 = maps.distance[0].at<float>(40, 30), d10 = maps.distance[0].at<float>(40, 25);
    EXPECT_NEAR(d10 - d5, 5.0f, 0.5f);
    EXPECT_LE(maps.distance[0].at<float>(40, 39), 1.0f);
    EXPECT_FLOAT_EQ((float)maps.max_distance, maps.distance[0].at<float>(40, 2));
    // the bin 90 degrees away (vertical gradients): no such edge anywhere -> truncated
    EXPECT_FLOAT_EQ((float)maps.max_distance, maps.distance[bins / 2].at<float>(40, 39));

    // a roi: the same distances inside, max_distance outside
    EdgeMaps part;
    computeEdgeMaps(img, part, EdgeRefineParams(), Rect(20, 10, 40, 60));
    EXPECT_FLOAT_EQ(maps.distance[0].at<float>(40, 30), part.distance[0].at<float>(40, 30));
    EXPECT_FLOAT_EQ((float)part.max_distance, part.distance[0].at<float>(5, 39));
    EXPECT_EQ(0, countNonZero(part.edges.rowRange(0, 10)));
    EXPECT_THROW(computeEdgeMaps(img, part, EdgeRefineParams(), Rect(100, 100, 10, 10)),
                 cv::Exception);
}

// The edge maps' distance transform is exact up to its truncation: equal to the distance to the
// nearest edge pixel found by brute force, for sparse and dense edges, reaches below and above
// the image's size, ROIs in and out, and beyond the 16-bit path (max_distance > 100, through
// cv::distanceTransform); the vector path gives the scalar path's values bit for bit.
TEST(Forestmod_PoseEdges, truncated_distance_is_exact_up_to_the_truncation)
{
    using cv::forestmod::detail::truncatedDistance;
    RNG rng(5);
    const double reaches[] = {1.5, 4, 15, 22.5, 130};
    const double densities[] = {0.0, 0.002, 0.05};
    for (double density : densities)
        for (double reach : reaches)
        {
            Mat big(70, 90, CV_8UC1, Scalar(0));
            for (int y = 0; y < big.rows; ++y)
                for (int x = 0; x < big.cols; ++x)
                    big.at<uchar>(y, x) = rng.uniform(0.0, 1.0) < density ? 255 : 0;
            big.at<uchar>(3, 80) = density > 0 ? 255 : 0;
            const Mat edges = big(Rect(3, 2, 83, 61)); // not continuous
            std::vector<Point> on;
            findNonZero(edges, on);
            Mat out_big(80, 100, CV_32FC1, Scalar(-1)), vec;
            Mat dist = out_big(Rect(5, 7, edges.cols, edges.rows));
            const bool was_optimized = useOptimized();
            setUseOptimized(false);
            truncatedDistance(edges, reach, dist);
            setUseOptimized(true);
            truncatedDistance(edges, reach, vec);
            setUseOptimized(was_optimized);
            ASSERT_EQ(CV_32FC1, vec.type());
            ASSERT_EQ(edges.size(), vec.size());
            EXPECT_EQ(0, cvtest::norm(dist, vec, NORM_INF)) << density << " " << reach;
            EXPECT_EQ(-1.f, out_big.at<float>(0, 0)); // written into the roi only
            int below = 0;
            for (int y = 0; y < edges.rows; ++y)
            {
                for (int x = 0; x < edges.cols; ++x)
                {
                    double d2 = 1e30;
                    for (size_t i = 0; i < on.size(); ++i)
                        d2 = std::min(d2, (double)(on[i].x - x) * (on[i].x - x)
                                          + (double)(on[i].y - y) * (on[i].y - y));
                    const double expected = std::min(std::sqrt(d2), reach);
                    below += expected < reach;
                    ASSERT_NEAR(expected, dist.at<float>(y, x), reach > 100 ? 1e-3 : 1e-6)
                        << density << " " << reach << " at " << x << "," << y;
                }
            }
            if (density > 0 && reach > 2)
            {
                EXPECT_GT(below, edges.rows); // the truncation does not hide everything
            }
        }
    Mat dist;
    EXPECT_THROW(truncatedDistance(Mat(4, 4, CV_32FC1, Scalar(0)), 5, dist), cv::Exception);
    EXPECT_THROW(truncatedDistance(Mat(4, 4, CV_8UC1, Scalar(0)), 0, dist), cv::Exception);
}

TEST(Forestmod_PoseEdges, params_roundtrip_and_bad_input)
{
    EdgeRefineParams p;
    p.orientations = 6;
    p.max_distance = 21;
    p.search_angle = 7;
    p.inner_edges = true;
    FileStorage fs(".yml", FileStorage::WRITE | FileStorage::MEMORY);
    fs << "p" << "{";
    p.write(fs);
    fs << "}";
    const String text = fs.releaseAndGetString();
    FileStorage in(text, FileStorage::READ | FileStorage::MEMORY);
    EdgeRefineParams q;
    q.read(in["p"]);
    EXPECT_EQ(6, q.orientations);
    EXPECT_EQ(21, q.max_distance);
    EXPECT_EQ(7, q.search_angle);
    EXPECT_TRUE(q.inner_edges);

    EdgeMaps maps;
    EXPECT_THROW(computeEdgeMaps(Mat(), maps), cv::Exception);
    EXPECT_THROW(computeEdgeMaps(Mat(10, 10, CV_32FC1, Scalar(0)), maps), cv::Exception);
    EdgeRefineParams bad;
    bad.orientations = 1;
    EXPECT_THROW(computeEdgeMaps(Mat(10, 10, CV_8UC1, Scalar(0)), maps, bad), cv::Exception);

    MeshRenderer mr(apeMesh(), Size(64, 48));
    computeEdgeMaps(Mat(48, 64, CV_8UC3, Scalar(0)), maps, p); // 6 bins
    const Matx33d K(60, 0, 32, 0, 60, 24, 0, 0, 1);
    // bins differ from the params
    EXPECT_THROW(refinePoseEdges(*mr.renderer, mr.handle, maps, K, Matx33d::eye(),
                                 Vec3d(0, 0, 800)), cv::Exception);
    // size differs from the renderer
    EdgeMaps big;
    computeEdgeMaps(Mat(96, 128, CV_8UC1, Scalar(0)), big);
    EXPECT_THROW(refinePoseEdges(*mr.renderer, mr.handle, big, K, Matx33d::eye(),
                                 Vec3d(0, 0, 800)), cv::Exception);
    // nothing visible: the start comes back with no points
    EdgeMaps ok;
    computeEdgeMaps(Mat(48, 64, CV_8UC1, Scalar(0)), ok);
    const EdgeRefineResult r = refinePoseEdges(*mr.renderer, mr.handle, ok, K, Matx33d::eye(),
                                               Vec3d(0, 0, -800));
    EXPECT_EQ(0, r.points);
    EXPECT_EQ(-800, r.t[2]);
}

}} // namespace
