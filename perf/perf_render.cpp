// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#include "perf_precomp.hpp"

#include "opencv2/core/utils/filesystem.hpp"
#include "../src/draw_mesh.hpp"

namespace opencv_test { namespace {

// LM-O ape (shipped) and driller (FORESTMOD_SHARED_DATA) meshes
static std::string meshPath(const std::string& name)
{
    if (name == "ape")
        return cvtest::findDataFile("lmo_mini/models/obj_000001.ply");
    const char* shared = getenv("FORESTMOD_SHARED_DATA");
    const std::string path = std::string(shared ? shared : "") + "/lmo/models/obj_000008.ply";
    if (!shared || !*shared || !cv::utils::fs::exists(path))
        throw SkipTestException("the driller mesh needs FORESTMOD_SHARED_DATA (../shared/data/lmo)");
    return path;
}

typedef TestBaseWithParam<std::string> Forestmod_Render;

// One template = one render() with colour, depth and mask at 640x480 (LM-O intrinsics), poses
// from the default sampler (level 2 hemisphere, 650-1150 mm, +-45 deg in-plane). Templates per
// second = 1 / the reported time.
PERF_TEST_P(Forestmod_Render, template_640x480, testing::Values("ape", "driller"))
{
    const Mesh mesh = Mesh::load(meshPath(GetParam()));
    const Matx33d K = lmoIntrinsics();
    Ptr<Renderer> renderer = Renderer::create(Size(640, 480));
    const int handle = renderer->addMesh(mesh);
    const Point3f c = mesh.center();
    const std::vector<ViewPose> poses = ViewSampler().poses(Point3d(c.x, c.y, c.z));
    Mat color, depth, mask;
    size_t pose_index = 0;
    // the same pose order for every sample: view i of the sampler, stepping by a prime
    TEST_CYCLE()
    {
        const ViewPose& p = poses[pose_index];
        pose_index = (pose_index + 97) % poses.size();
        renderer->render(handle, p.R, p.t, K, color, depth, mask);
    }
    ASSERT_EQ(CV_16UC1, depth.type());
    ASSERT_GT(countNonZero(mask), 0);
    SANITY_CHECK_NOTHING();
}

// The whole renderTemplates() pipeline on a small sampler (level 0: 6 views x 3 in-plane),
// including context creation and the mesh upload: the fixed cost of a call.
PERF_TEST_P(Forestmod_Render, renderTemplates_18_views, testing::Values("ape"))
{
    const Mesh mesh = Mesh::load(meshPath(GetParam()));
    const Matx33d K = lmoIntrinsics();
    ViewSampler::Params p = ViewSampler::Params::coarse();
    p.inplane_min = -15;
    p.inplane_max = 15;
    p.inplane_step = 15;
    const ViewSampler sampler(p);
    std::vector<TemplateView> out;
    TEST_CYCLE()
    {
        renderTemplates(mesh, sampler, K, Size(640, 480), out);
    }
    ASSERT_EQ(18u, out.size());
    SANITY_CHECK_NOTHING();
}

typedef TestBaseWithParam<tuple<std::string, int, bool> > Forestmod_DrawMesh;

// What the detector's pose stage and verification draw for one hypothesis: drawMesh() of the
// mesh simplified by vertex clustering (divisor 0: the detector's cells, drawingCell(); N > 0:
// cells of 1 / N of the diameter) into the crop around it, depth and the face of each pixel, at
// the default sampler's poses (650-1150 mm) in a 640x480 image; with clusters (the detector's
// way, clusterFaces(): the clusters facing away skipped) or every face tested.
PERF_TEST_P(Forestmod_DrawMesh, coarse_mesh_640x480,
            testing::Combine(testing::Values("ape", "driller"), testing::Values(0, 32),
                             testing::Bool()))
{
    namespace fd = cv::forestmod::detail;
    const Mesh mesh = Mesh::load(meshPath(get<0>(GetParam())));
    const int divisor = get<1>(GetParam());
    Mesh coarse = fd::coarseMesh(mesh, divisor > 0 ? mesh.diameter() / divisor
                                                   : fd::drawingCell(mesh.diameter()));
    const int winding = fd::closedWinding(coarse);
    const bool clustered = get<2>(GetParam());
    const fd::FaceClusters clusters = clustered ? fd::clusterFaces(coarse, winding)
                                                : fd::FaceClusters();
    const Matx33d K = lmoIntrinsics();
    const Point3f c = mesh.center();
    const std::vector<ViewPose> poses = ViewSampler().poses(Point3d(c.x, c.y, c.z));
    fd::Drawing d;
    size_t pose_index = 0;
    TEST_CYCLE()
    {
        const ViewPose& p = poses[pose_index];
        pose_index = (pose_index + 97) % poses.size();
        fd::drawMesh(coarse, winding, K, p.R, p.t, Size(640, 480), 8, d,
                     clustered ? &clusters : 0);
    }
    ASSERT_GT(countNonZero(d.mask), 0);
    ASSERT_EQ(CV_32SC1, d.face.type());
    SANITY_CHECK_NOTHING();
}

typedef TestBaseWithParam<std::string> Forestmod_MeshSilhouette;

// What the edge alignment takes instead of a drawing for its points: meshSilhouette() of the
// detector's mesh (drawingCell(), clusterFaces() order) at the default sampler's poses in a
// 640x480 image, up to 400 points; to be read against Forestmod_DrawMesh (divisor 0, clusters).
PERF_TEST_P(Forestmod_MeshSilhouette, coarse_mesh_640x480, testing::Values("ape", "driller"))
{
    namespace fd = cv::forestmod::detail;
    const Mesh mesh = Mesh::load(meshPath(GetParam()));
    Mesh coarse = fd::coarseMesh(mesh, fd::drawingCell(mesh.diameter()));
    const int winding = fd::closedWinding(coarse);
    fd::clusterFaces(coarse, winding);
    const fd::SilhouetteEdges edges = fd::silhouetteEdges(coarse, winding);
    const Matx33d K = lmoIntrinsics();
    const Point3f c = mesh.center();
    const std::vector<ViewPose> poses = ViewSampler().poses(Point3d(c.x, c.y, c.z));
    std::vector<fd::SilhouettePoint> pts;
    size_t pose_index = 0;
    TEST_CYCLE()
    {
        const ViewPose& p = poses[pose_index];
        pose_index = (pose_index + 97) % poses.size();
        fd::meshSilhouette(coarse, edges, K, p.R, p.t, Size(640, 480), 400, pts);
    }
    ASSERT_GT(pts.size(), 50u);
    SANITY_CHECK_NOTHING();
}

}} // namespace
