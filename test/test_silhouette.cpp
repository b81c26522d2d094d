// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The outline of a closed mesh from its silhouette edges (src/silhouette.cpp), the edge
// alignment's points: against the drawn mask, on a cube whose silhouette is known exactly, and on
// meshes and poses it does not take.

#include "test_precomp.hpp"
#include "test_pose_common.hpp"

namespace opencv_test { namespace {

namespace fd = cv::forestmod::detail;

static Point2d project(const Matx33d& K, const Matx33d& R, const Vec3d& t, const Point3f& p)
{
    const Vec3d q = K * (R * Vec3d(p.x, p.y, p.z) + t);
    return Point2d(q[0] / q[2], q[1] / q[2]);
}

// The orientation of a direction modulo 180 degrees, in degrees.
static double orientation(double x, double y)
{
    double a = std::atan2(y, x) * 180 / CV_PI;
    return a < 0 ? a + 180 : a;
}

static double orientationDifference(double a, double b)
{
    const double d = std::fabs(a - b);
    return std::min(d, 180 - d);
}

// meshSilhouette() of `mesh` at (R, t) against its drawing (drawMesh()): every point lies within
// a pixel of the drawn mask's boundary (its pixels on either side; none where the image border
// cuts the object), the points cover that boundary, and their normals are the mask's; the vector
// and scalar paths give the same points; at least min_inside of them round to the mask's own
// pixels (half a pixel in; on long straight edges the rounding puts more of them just outside).
// False when the object covers fewer than 50 pixels (nothing tested); cut is set when the image
// border cuts it.
static bool outlineFollowsTheDrawing(const Mesh& mesh, int winding,
                                     const fd::FaceClusters* clusters,
                                     const fd::SilhouetteEdges& edges, const Matx33d& K,
                                     const Matx33d& R, const Vec3d& t, Size image,
                                     double min_inside, bool& cut)
{
    fd::Drawing d;
    fd::drawMesh(mesh, winding, K, R, t, image, fd::kDrawMargin, d, clusters);
    if (countNonZero(d.mask) < 50)
        return false;
    // the mask's boundary on both sides, in the image; neighbours off the image do not count
    Mat mask(image, CV_8U, Scalar(0));
    d.mask.copyTo(mask(d.rect));
    Mat band(image, CV_8U, Scalar(0)), inner(image, CV_8U, Scalar(0));
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
        {
            const Point n4[4] = { Point(x - 1, y), Point(x + 1, y), Point(x, y - 1),
                                  Point(x, y + 1) };
            for (int k = 0; k < 4; ++k)
                if (Rect(Point(), image).contains(n4[k])
                    && mask.at<uchar>(n4[k]) != mask.at<uchar>(y, x))
                {
                    band.at<uchar>(y, x) = 255;
                    inner.at<uchar>(y, x) = mask.at<uchar>(y, x);
                }
        }
    cut = countNonZero(mask.row(0)) + countNonZero(mask.col(0))
        + countNonZero(mask.row(image.height - 1)) + countNonZero(mask.col(image.width - 1))
        > 0;
    std::vector<fd::SilhouettePoint> pts, scalar;
    fd::meshSilhouette(mesh, edges, K, R, t, image, 100000, pts);
    cv::setUseOptimized(false);
    fd::meshSilhouette(mesh, edges, K, R, t, image, 100000, scalar);
    cv::setUseOptimized(true);
    EXPECT_EQ(pts.size(), scalar.size());
    for (size_t k = 0; k < pts.size() && k < scalar.size(); ++k)
    {
        EXPECT_EQ(pts[k].model, scalar[k].model) << k;
        EXPECT_EQ(pts[k].normal, scalar[k].normal) << k;
    }
    const int boundary = countNonZero(inner);
    EXPECT_GT((int)pts.size(), boundary / 2);
    EXPECT_LT((int)pts.size(), boundary * 3 / 2);
    Mat to_band, to_points, covered(image, CV_8U, Scalar(255)), gx, gy, blurred;
    distanceTransform(band == 0, to_band, DIST_L2, DIST_MASK_PRECISE);
    GaussianBlur(mask, blurred, Size(5, 5), 0);
    Sobel(blurred, gx, CV_32F, 1, 0);
    Sobel(blurred, gy, CV_32F, 0, 1);
    int agreeing = 0, inside = 0, off_band = 0;
    for (size_t k = 0; k < pts.size(); ++k)
    {
        const Point2d p = project(K, R, t, pts[k].model);
        EXPECT_TRUE(p.x > -1 && p.y > -1 && p.x < image.width && p.y < image.height) << k << p;
        const Point q(std::min(std::max(cvRound(p.x), 0), image.width - 1),
                      std::min(std::max(cvRound(p.y), 0), image.height - 1));
        off_band += to_band.at<float>(q) > 1.5f;
        inside += mask.at<uchar>(q) != 0; // half a pixel in: mostly on the object's pixels
        covered.at<uchar>(q) = 0;
        // the mask's gradient at the nearest boundary pixel
        double best = 1e9, mask_orientation = 0;
        for (int dy = -2; dy <= 2; ++dy)
            for (int dx = -2; dx <= 2; ++dx)
            {
                const Point r = q + Point(dx, dy);
                if (Rect(Point(), image).contains(r) && band.at<uchar>(r)
                    && dx * dx + dy * dy < best)
                {
                    best = dx * dx + dy * dy;
                    mask_orientation = orientation(gx.at<float>(r), gy.at<float>(r));
                }
            }
        agreeing += orientationDifference(orientation(pts[k].normal[0], pts[k].normal[1]),
                                          mask_orientation) <= 30;
    }
    EXPECT_EQ(off_band, 0);
    EXPECT_GE(agreeing, 0.9 * pts.size());
    EXPECT_GE(inside, min_inside * pts.size());
    distanceTransform(covered, to_points, DIST_L2, DIST_MASK_PRECISE);
    int near = 0, far = 0; // the boundary but on the image's outermost pixels
    for (int y = 1; y + 1 < image.height; ++y)
        for (int x = 1; x + 1 < image.width; ++x)
            if (inner.at<uchar>(y, x))
                (to_points.at<float>(y, x) <= 1.5f ? near : far)++;
    EXPECT_GE(near, 0.97 * (near + far));
    return true;
}

// The outline at the ape's views (some cut by the image border) stands for the drawing's
// boundary, which the edge alignment used before (outlineFollowsTheDrawing()).
TEST(Forestmod_Silhouette, outline_follows_the_drawn_mask)
{
    const Mesh ape = Mesh::load(cvtest::findDataFile("lmo_mini/models/obj_000001.ply"));
    Mesh coarse = fd::coarseMesh(ape, fd::drawingCell(ape.diameter()));
    const int winding = fd::closedWinding(coarse);
    ASSERT_NE(winding, 0);
    const fd::FaceClusters clusters = fd::clusterFaces(coarse, winding);
    const fd::SilhouetteEdges edges = fd::silhouetteEdges(coarse, winding);
    ASSERT_EQ(edges.faces.size(), edges.ends.size());
    ASSERT_EQ(edges.plane.size(), 4 * coarse.faces.size());
    const Matx33d K = lmoIntrinsics();
    const Size image(640, 480);
    const std::vector<ViewPose> views = pose_test::hemisphereViews(ape, { 300.0, 700.0, 1400.0 });
    int tested = 0, cut = 0;
    for (size_t i = 0; i < views.size(); i += 5)
    {
        Vec3d t = views[i].t;
        if (i % 2) // moved towards a corner: cut by the image border
            t += Vec3d(0.45 * t[2] * image.width / K(0, 0), 0.4 * t[2] * image.height / K(1, 1),
                       0);
        bool c = false;
        SCOPED_TRACE(cv::format("view %d", (int)i));
        if (outlineFollowsTheDrawing(coarse, winding, &clusters, edges, K, views[i].R, t, image,
                                     0.75, c))
        {
            ++tested;
            cut += c;
        }
    }
    EXPECT_GE(tested, 15);
    EXPECT_GE(cut, 3);
}

// The edges' blocks (SilhouetteEdges::block_start, block_chunks) hold the chunks of every face of
// their edges. At the ape's views, a block whose chunks all look one way (the listing passes over
// it) holds no silhouette edge, such blocks are a good share of them, and the outline with the
// blocks (cv::useOptimized()) is the outline without them, point for point.
TEST(Forestmod_Silhouette, edge_blocks_pass_over_uniform_chunks_only)
{
    const Mesh ape = Mesh::load(cvtest::findDataFile("lmo_mini/models/obj_000001.ply"));
    Mesh coarse = fd::coarseMesh(ape, fd::drawingCell(ape.diameter()));
    const int winding = fd::closedWinding(coarse);
    ASSERT_NE(winding, 0);
    fd::clusterFaces(coarse, winding);
    const fd::SilhouetteEdges edges = fd::silhouetteEdges(coarse, winding);
    const int ne = (int)edges.faces.size(), nf = (int)coarse.faces.size();
    const int B = fd::SilhouetteEdges::kBlockEdges, C = fd::SilhouetteEdges::kChunkFaces;
    const int missing = (nf + C - 1) / C, mixed = missing + 1, nb = (ne + B - 1) / B;
    ASSERT_EQ(edges.block_start.size(), (size_t)nb + 1);
    ASSERT_EQ((size_t)edges.block_start.back(), edges.block_chunks.size());
    for (int b = 0; b < nb; ++b)
    {
        const int* first = edges.block_chunks.data() + edges.block_start[b];
        const int* last = edges.block_chunks.data() + edges.block_start[b + 1];
        ASSERT_LT(first, last) << b;
        if (*first == mixed)
            continue;
        ASSERT_LE(last - first, (int)fd::SilhouetteEdges::kBlockChunks) << b;
        for (int e = b * B; e < std::min(ne, (b + 1) * B); ++e)
            for (int k = 0; k < 2; ++k)
            {
                const int f = edges.faces[e][k], c = f >= 0 ? f / C : missing;
                ASSERT_TRUE(std::find(first, last, c) != last) << e;
            }
    }
    const Matx33d K = lmoIntrinsics();
    const std::vector<ViewPose> views = pose_test::hemisphereViews(ape, { 400.0, 1000.0 });
    double uniform_share = 0;
    int n = 0;
    for (size_t i = 0; i < views.size(); i += 3, ++n)
    {
        const Matx33d& R = views[i].R;
        const Vec3d& t = views[i].t;
        // each face as the library tests it, each chunk's faces: 0 none front, 2 all, 1 some
        const Vec3d c = -(R.t() * t);
        std::vector<int> front(nf), state(missing + 2, 0);
        for (int f = 0; f < nf; ++f)
            front[f] = edges.plane[f] * (float)c[0] + edges.plane[nf + f] * (float)c[1]
                    + edges.plane[2 * nf + f] * (float)c[2]
                > edges.plane[3 * nf + f];
        for (int k = 0; k < missing; ++k)
        {
            const int end = std::min(nf, (k + 1) * C);
            const int on = (int)std::count(front.begin() + k * C, front.begin() + end, 1);
            state[k] = on == 0 ? 0 : on == end - k * C ? 2 : 1;
        }
        state[mixed] = 1;
        int uniform = 0;
        for (int b = 0; b < nb; ++b)
        {
            std::set<int> states;
            for (int j = edges.block_start[b]; j < edges.block_start[b + 1]; ++j)
                states.insert(state[edges.block_chunks[j]]);
            if (states.size() != 1 || *states.begin() == 1)
                continue;
            ++uniform;
            for (int e = b * B; e < std::min(ne, (b + 1) * B); ++e)
            {
                const int f1 = edges.faces[e][1];
                ASSERT_EQ(front[edges.faces[e][0]], f1 >= 0 ? front[f1] : 0) << i << " " << e;
            }
        }
        uniform_share += uniform / (double)nb;
        std::vector<fd::SilhouettePoint> with, without;
        fd::meshSilhouette(coarse, edges, K, R, t, Size(640, 480), 400, with);
        cv::setUseOptimized(false);
        fd::meshSilhouette(coarse, edges, K, R, t, Size(640, 480), 400, without);
        cv::setUseOptimized(true);
        ASSERT_EQ(with.size(), without.size()) << i;
        for (size_t k = 0; k < with.size(); ++k)
        {
            ASSERT_EQ(with[k].model, without[k].model) << i << " " << k;
            ASSERT_EQ(with[k].normal, without[k].normal) << i << " " << k;
        }
    }
    ASSERT_GT(n, 20);
    EXPECT_GT(uniform_share / n, 0.5) << uniform_share / n; // 0.64 at commit time
}

// A closed prism of height h over an L of three squares of side a (corners (0, 0), (2a, 0),
// (2a, a), (a, a), (a, 2a), (0, 2a) counter-clockwise: vertices 0-5 at z = 0, 6-11 at z = h),
// faces turning counter-clockwise seen from outside. Its one concave edge joins vertices 3 and 9.
static Mesh lPrism(float a, float h)
{
    Mesh m;
    const Point2f L[6] = { Point2f(0, 0), Point2f(2 * a, 0), Point2f(2 * a, a), Point2f(a, a),
                           Point2f(a, 2 * a), Point2f(0, 2 * a) };
    for (int z = 0; z < 2; ++z)
        for (int i = 0; i < 6; ++i)
            m.vertices.push_back(Point3f(L[i].x, L[i].y, z ? h : 0.f));
    for (int i = 0; i < 6; ++i)
    {
        const int j = (i + 1) % 6;
        m.faces.push_back(Vec3i(i, j, j + 6));
        m.faces.push_back(Vec3i(i, j + 6, i + 6));
    }
    const int cap[4][3] = { { 0, 1, 2 }, { 0, 2, 3 }, { 0, 3, 4 }, { 0, 4, 5 } };
    for (int k = 0; k < 4; ++k)
    {
        m.faces.push_back(Vec3i(cap[k][0] + 6, cap[k][1] + 6, cap[k][2] + 6));
        m.faces.push_back(Vec3i(cap[k][0], cap[k][2], cap[k][1]));
    }
    m.colors.assign(m.vertices.size(), Vec3b(128, 128, 128));
    m.computeNormals();
    return m;
}

// The L prism's outline follows the drawing, from the views where its concave edge lies between a
// face that looks towards the camera and one that does not (the edge is then behind the prism's
// other arm, and its line falls inside the outline or under a nearer edge) as from the others.
// All 30 of its edges are kept (17 convex, 12 flat, 1 concave).
TEST(Forestmod_Silhouette, concave_prism_outline_follows_the_drawing)
{
    const float a = 30.f;
    const Mesh prism = lPrism(a, 40.f);
    ASSERT_EQ(fd::closedWinding(prism), 1);
    const fd::SilhouetteEdges edges = fd::silhouetteEdges(prism, 1);
    ASSERT_EQ(edges.faces.size(), 30u);
    int kept = 0;
    for (size_t e = 0; e < edges.ends.size(); ++e)
        kept += edges.ends[e] == Vec2i(3, 9) || edges.ends[e] == Vec2i(1, 7);
    EXPECT_EQ(kept, 2); // the concave edge and a convex one
    const Matx33d K = lmoIntrinsics();
    const std::vector<ViewPose> views = pose_test::hemisphereViews(prism, { 250.0, 400.0 });
    int tested = 0, hidden = 0;
    for (size_t i = 0; i < views.size(); ++i)
    {
        const Vec3d c = -(views[i].R.t() * views[i].t); // the camera centre, model frame
        // the concave edge's faces: normals +y (the L's side from (2a, a) to (a, a)) and +x
        const bool different = (c[1] > a) != (c[0] > a);
        bool cut = false;
        SCOPED_TRACE(cv::format("view %d", (int)i));
        if (outlineFollowsTheDrawing(prism, 1, 0, edges, K, views[i].R, views[i].t,
                                     Size(640, 480), 0.4, cut))
        {
            ++tested;
            hidden += different;
        }
    }
    EXPECT_GE(tested, 20);
    EXPECT_GE(hidden, 5);
}

// A cube seen over a corner, near the camera (its far edges recede): every point lies just inside
// one of the cube's edges that the outline is made of (two coordinates at +-h, never on a face's
// diagonal), its projection half a pixel from that edge's projection on the outline's inner side
// and across it from a pixel centre (through perspective: the point of the edge whose projection
// is nearest the pixel, moved in), and its normal is perpendicular to that edge's projection.
TEST(Forestmod_Silhouette, cube_outline_lies_on_its_edges)
{
    const float h = 50.f;
    const Mesh box = closedCube(h);
    const int winding = fd::closedWinding(box);
    ASSERT_EQ(winding, 1);
    const fd::SilhouetteEdges edges = fd::silhouetteEdges(box, winding);
    EXPECT_EQ(edges.faces.size(), 18u); // 12 edges of the cube, 6 diagonals
    const Matx33d K = lmoIntrinsics();
    Matx33d R;
    Rodrigues(Vec3d(0.6, -0.7, 0.2), R);
    const Vec3d t(20, -10, 260);
    std::vector<fd::SilhouettePoint> pts;
    fd::meshSilhouette(box, edges, K, R, t, Size(640, 480), 100000, pts);
    ASSERT_GT(pts.size(), 200u);
    const Point2d centre = project(K, R, t, Point3f(0, 0, 0));
    const float near = 0.5f; // mm: half a pixel is at most 0.3 mm at these depths
    int on_edges = 0, tested = 0;
    for (size_t k = 0; k < pts.size(); ++k)
    {
        const Point3f& m = pts[k].model;
        const bool at_x = std::fabs(std::fabs(m.x) - h) < near,
                   at_y = std::fabs(std::fabs(m.y) - h) < near,
                   at_z = std::fabs(std::fabs(m.z) - h) < near;
        ASSERT_GE(at_x + at_y + at_z, 2) << k << " " << m; // at an edge, not on a diagonal
        ASSERT_TRUE(std::max(std::fabs(m.x), std::max(std::fabs(m.y), std::fabs(m.z)))
                    < h + 1e-3f) << k << " " << m; // inside the cube
        // the edge by m: the coordinate not at +-h runs along it, the others are the edge's
        Point3f a(at_x ? (m.x > 0 ? h : -h) : -h, at_y ? (m.y > 0 ? h : -h) : -h,
                  at_z ? (m.z > 0 ? h : -h) : -h);
        Point3f b = a;
        if (!at_x)
            b.x = h;
        else if (!at_y)
            b.y = h;
        else
            b.z = h;
        const Point2d pa = project(K, R, t, a), pb = project(K, R, t, b);
        const Point2d p = project(K, R, t, m);
        const Point2d e = pb - pa, u = e * (1.0 / cv::norm(e));
        const double along = orientation(e.x, e.y), normal = orientation(pts[k].normal[0],
                                                                         pts[k].normal[1]);
        on_edges += orientationDifference(along + 90, normal) <= 25;
        const double s = (p - pa).dot(u) / cv::norm(e);
        if (at_x + at_y + at_z == 3 || s < 0.05 || s > 0.95)
            continue; // at a corner: the outline turns there
        // half a pixel from the projected edge, on the side of the cube's centre
        const double off = (p - pa).cross(u), inner = (centre - pa).cross(u);
        ASSERT_GT(std::fabs(off), 0.4) << k;
        ASSERT_LT(std::fabs(off), 0.55) << k;
        ASSERT_GT(off * inner, 0) << k;
        // the foot on the projected edge is (nearly) the nearest point of it to a pixel centre
        const Point2d foot = pa + u * (p - pa).dot(u);
        double across = 1e9;
        for (int dy = -2; dy <= 2; ++dy)
            for (int dx = -2; dx <= 2; ++dx)
            {
                const Point2d c(cvRound(foot.x) + dx, cvRound(foot.y) + dy);
                if (cv::norm(c - foot) <= 1.5)
                    across = std::min(across, std::fabs((c - foot).dot(u)));
            }
        ASSERT_LE(across, 0.25) << k;
        ++tested;
    }
    EXPECT_GE(on_edges, 0.9 * pts.size());
    EXPECT_GE(tested, 0.5 * pts.size());
}

// Two cubes seen face on, the second twice as far and (nearly) twice as large behind the first:
// their outlines fall on the same pixels, and the points are the nearer cube's.
TEST(Forestmod_Silhouette, the_nearer_edge_on_a_pixel_gives_the_point)
{
    const float h = 40.f;
    Mesh two = closedCube(h);
    const Mesh back = closedCube(1.99f * h);
    for (size_t f = 0; f < back.faces.size(); ++f)
        two.faces.push_back(back.faces[f] + Vec3i::all(8));
    for (size_t v = 0; v < back.vertices.size(); ++v)
        two.vertices.push_back(back.vertices[v] + Point3f(0, 0, 300));
    two.colors.assign(16, Vec3b(128, 128, 128));
    two.computeNormals();
    ASSERT_EQ(fd::closedWinding(two), 1);
    const fd::SilhouetteEdges edges = fd::silhouetteEdges(two, 1);
    std::vector<fd::SilhouettePoint> pts;
    fd::meshSilhouette(two, edges, lmoIntrinsics(), Matx33d::eye(), Vec3d(0, 0, 300),
                       Size(640, 480), 100000, pts);
    ASSERT_GT(pts.size(), 200u);
    int front = 0;
    for (size_t k = 0; k < pts.size(); ++k)
        front += pts[k].model.z < 0; // the first cube's front face (z = -h)
    EXPECT_GE(front, 0.95 * pts.size());
}

// A square of two triangles (an open surface: its edges have one face each) seen from its front:
// the outline is its border; seen from behind (the faces a closed mesh never shows), none.
TEST(Forestmod_Silhouette, open_square_outline_is_its_border)
{
    Mesh square;
    const float h = 40.f;
    square.vertices = { Point3f(-h, -h, 0), Point3f(h, -h, 0), Point3f(h, h, 0),
                        Point3f(-h, h, 0) };
    square.faces = { Vec3i(0, 2, 1), Vec3i(0, 3, 2) }; // normal -z: towards a camera at z < 0
    square.colors.assign(4, Vec3b(128, 128, 128));
    square.computeNormals();
    const fd::SilhouetteEdges edges = fd::silhouetteEdges(square, 1);
    EXPECT_EQ(edges.faces.size(), 5u);
    const Matx33d K = lmoIntrinsics();
    std::vector<fd::SilhouettePoint> pts;
    fd::meshSilhouette(square, edges, K, Matx33d::eye(), Vec3d(0, 0, 400), Size(640, 480),
                       100000, pts);
    const double side = 2 * h * K(0, 0) / 400; // px
    ASSERT_GT(pts.size(), 3.5 * side);
    ASSERT_LT(pts.size(), 4.5 * side);
    for (size_t k = 0; k < pts.size(); ++k) // half a pixel inside: 0.35 mm at 400 mm
    {
        const float r = std::max(std::fabs(pts[k].model.x), std::fabs(pts[k].model.y));
        ASSERT_LT(r, h) << k;
        ASSERT_GT(r, h - 0.5f) << k;
    }
    Matx33d turned; // seen from behind
    Rodrigues(Vec3d(0, CV_PI, 0), turned);
    fd::meshSilhouette(square, edges, K, turned, Vec3d(0, 0, 400), Size(640, 480), 100000, pts);
    EXPECT_TRUE(pts.empty());
}

// What meshSilhouette() and the drawers leave alone: an open mesh has no silhouette edges, a
// drawer without them (or with another mesh's) says it has no silhouette, a pose behind the camera
// or off the image has no points, max_points spaces them along the outline, and edges of another
// mesh raise.
TEST(Forestmod_Silhouette, poses_and_meshes_without_an_outline)
{
    const Mesh box = closedCube(40.f);
    Mesh open = box;
    open.faces.pop_back();
    EXPECT_EQ(fd::closedWinding(open), 0);
    const fd::SilhouetteEdges none = fd::silhouetteEdges(open, 0);
    EXPECT_TRUE(none.faces.empty() && none.plane.empty());
    const fd::SilhouetteEdges edges = fd::silhouetteEdges(box, 1);
    const Matx33d K = lmoIntrinsics();
    const Size image(640, 480);
    std::vector<fd::SilhouettePoint> pts;
    const fd::MeshDrawer without(box, 1, image), with(box, 1, image, 0, 0, &edges),
        other(open, 1, image, 0, 0, &edges);
    EXPECT_FALSE(without.silhouette(K, Matx33d::eye(), Vec3d(0, 0, 500), 400, pts));
    EXPECT_FALSE(other.silhouette(K, Matx33d::eye(), Vec3d(0, 0, 500), 400, pts));
    ASSERT_TRUE(with.silhouette(K, Matx33d::eye(), Vec3d(0, 0, 500), 100000, pts));
    const size_t all = pts.size();
    ASSERT_GT(all, 100u);
    ASSERT_TRUE(with.silhouette(K, Matx33d::eye(), Vec3d(0, 0, 500), 50, pts));
    EXPECT_EQ(pts.size(), 50u);
    with.silhouette(K, Matx33d::eye(), Vec3d(0, 0, -500), 400, pts); // behind the camera
    EXPECT_TRUE(pts.empty());
    with.silhouette(K, Matx33d::eye(), Vec3d(0, 0, 30), 400, pts); // through the camera
    EXPECT_TRUE(pts.empty());
    with.silhouette(K, Matx33d::eye(), Vec3d(3000, 0, 500), 400, pts); // off the image
    EXPECT_TRUE(pts.empty());
    // more than twice the image's width (the cube's 80 mm seen from 40 mm): drawn instead
    EXPECT_FALSE(with.silhouette(K, Matx33d::eye(), Vec3d(0, 0, 80), 400, pts));
    EXPECT_TRUE(pts.empty());
    EXPECT_TRUE(with.silhouette(K, Matx33d::eye(), Vec3d(0, 0, 160), 100000, pts));
    EXPECT_GT(pts.size(), 100u);
    fd::meshSilhouette(box, edges, K, Matx33d::eye(), Vec3d(0, 0, 500), image, 0, pts);
    EXPECT_TRUE(pts.empty());
    EXPECT_THROW(fd::meshSilhouette(open, edges, K, Matx33d::eye(), Vec3d(0, 0, 500), image,
                                    400, pts),
                 cv::Exception);
}

}} // namespace
