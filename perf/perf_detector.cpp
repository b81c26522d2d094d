// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// match() per VGA RGB-D frame: forestmod (1 and 5 trees) and cv::linemod::Detector with the
// same modalities, templates and frames, for 1 object and 8 objects (LM-O meshes).

#include "perf_precomp.hpp"

#include "opencv2/core/utils/filesystem.hpp"

namespace opencv_test { namespace {

// obj 1 ships with the project; the other seven come from ../shared (FORESTMOD_SHARED_DATA)
static std::vector<std::string> meshPaths(int count)
{
    std::vector<std::string> paths;
    paths.push_back(cvtest::findDataFile("lmo_mini/models/obj_000001.ply"));
    const char* shared = getenv("FORESTMOD_SHARED_DATA");
    const int others[] = { 5, 6, 8, 9, 10, 11, 12 };
    for (int i = 0; (int)paths.size() < count && i < 7; ++i)
    {
        if (!shared || !*shared)
            break;
        const std::string p = cv::format("%s/lmo/models/obj_%06d.ply", shared, others[i]);
        if (utils::fs::exists(p))
            paths.push_back(p);
    }
    return paths;
}

struct TemplateSet
{
    std::vector<std::vector<TemplateView> > views; // per object
    std::vector<Mesh> meshes;
};

// rendered once per process: level-1 hemisphere, two distances, three in-plane angles
static const TemplateSet& templates(int objects)
{
    static std::map<int, TemplateSet> cache;
    if (cache.count(objects))
        return cache[objects];
    TemplateSet& set = cache[objects];
    ViewSampler::Params sp;
    sp.level = 1;
    sp.min_elevation = 10;
    sp.radii.clear();
    sp.radii.push_back(750);
    sp.radii.push_back(1000);
    sp.inplane_min = -20;
    sp.inplane_max = 20;
    sp.inplane_step = 20;
    const std::vector<std::string> paths = meshPaths(objects);
    for (size_t i = 0; i < paths.size(); ++i)
    {
        set.meshes.push_back(Mesh::load(paths[i]));
        set.views.push_back(std::vector<TemplateView>());
        renderTemplates(set.meshes.back(), ViewSampler(sp), lmoIntrinsics(), szVGA, set.views.back());
    }
    return set;
}

template <typename D>
static void addAll(D& det, const TemplateSet& set)
{
    for (size_t o = 0; o < set.views.size(); ++o)
        for (size_t i = 0; i < set.views[o].size(); ++i)
        {
            const TemplateView& v = set.views[o][i];
            std::vector<Mat> src;
            src.push_back(v.color);
            src.push_back(v.depth);
            src.push_back(v.color);
            det.addTemplate(src, cv::format("obj%d", (int)o), v.mask);
        }
}

static std::vector<Ptr<linemod::Modality> > modalities()
{
    std::vector<Ptr<linemod::Modality> > m;
    m.push_back(linemod::Modality::create("ColorGradient"));
    m.push_back(linemod::Modality::create("DepthNormal"));
    m.push_back(ColorHue::create());
    return m;
}

static std::vector<int> Tpyr()
{
    std::vector<int> T;
    T.push_back(5);
    T.push_back(8);
    return T;
}

static std::vector<Mat> scene(const TemplateSet& set)
{
    Ptr<Renderer> renderer = Renderer::create(szVGA);
    SceneSynthesizer synth(renderer, lmoIntrinsics());
    for (size_t i = 0; i < set.meshes.size(); ++i)
        synth.addObject(set.meshes[i]);
    std::vector<Mat> bg(1, imread(cvtest::findDataFile("lmo_mini/test/000002/rgb/000902.png")));
    synth.setBackgrounds(bg);
    RNG rng(17);
    const TemplateView& v = set.views[0][set.views[0].size() / 3];
    const SyntheticScene s = synth.render(0, v.R, v.t, rng);
    std::vector<Mat> src;
    src.push_back(s.color);
    src.push_back(s.depth);
    src.push_back(s.color);
    return src;
}

CV_ENUM(DetectorKind, 0, 1, 5) // 0: cv::linemod, 1 and 5: forestmod with that many trees
typedef tuple<DetectorKind, int> MatchParams;
typedef TestBaseWithParam<MatchParams> Forestmod_Match;

PERF_TEST_P(Forestmod_Match, vga_rgbd, Combine(DetectorKind::all(), Values(1, 8)))
{
    const int kind = get<0>(GetParam()), objects = get<1>(GetParam());
    const TemplateSet& set = templates(objects);
    if ((int)set.views.size() < objects)
        throw SkipTestException("FORESTMOD_SHARED_DATA with the LM-O meshes is needed for 8 objects");
    const std::vector<Mat> src = scene(set);
    std::vector<linemod::Match> matches;
    if (kind == 0)
    {
        linemod::Detector det(modalities(), Tpyr());
        addAll(det, set);
        TEST_CYCLE() det.match(src, 80.f, matches);
    }
    else
    {
        DetectorParams p;
        p.forest.num_trees = kind;
        cv::forestmod::Detector det(modalities(), Tpyr(), p);
        addAll(det, set);
        det.train();
        TEST_CYCLE() det.match(src, 80.f, matches);
    }
    ASSERT_FALSE(matches.empty());
    SANITY_CHECK_NOTHING();
}

}} // namespace
