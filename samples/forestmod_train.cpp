// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Meshes -> one forestmod model file: renders templates on the view hemisphere of every mesh
// (cv::forestmod::ViewSampler), adds them with their poses, trains the forest, saves the model.

#include <opencv2/core.hpp>
#include <opencv2/core/utils/filesystem.hpp>
#include <opencv2/forestmod.hpp>

#include "sample_utils.hpp"
#include <cstdio>
#include <iostream>
#include <sstream>

using cv::forestmod::samples::splitList;
using cv::forestmod::samples::lmoIntrinsics;

static const char* keys
    = "{help h usage ?  |          | print this message }"
      "{meshes          |          | comma-separated mesh files (PLY, OBJ, STL, ...; mm) }"
      "{ids             |          | comma-separated class ids, one per mesh (default: file names) }"
      "{out             |          | output model file (.yml.gz, .yml, .json) }"
      "{camera          |          | BOP camera.json with the intrinsics (default: LM-O's Kinect) }"
      "{modalities      | linemod  | line (gradient + hue) or linemod (gradient + depth normal + hue) }"
      "{level           | 2        | icosahedron subdivisions of the view hemisphere }"
      "{min_elevation   | 0        | lowest camera elevation (degrees) }"
      "{max_elevation   | 90       | highest camera elevation (degrees) }"
      "{radii           | 650,800,950,1100 | camera distances (mm) }"
      "{inplane         | -45,45,15 | in-plane rotations: min,max,step (degrees) }"
      "{trees           | 1        | trees of the forest (paper: 1 or 5) }"
      "{fuzzy           | -1       | fuzzy margin xi of the splits (default: the library's) }"
      "{scale           | 1        | mesh units -> mm (1000 for meshes in metres) }"
      "{force           |          | overwrite the output file }";

static std::vector<double> numbers(const std::string& s)
{
    std::vector<double> out;
    std::vector<std::string> items = splitList(s);
    for (size_t i = 0; i < items.size(); ++i)
        out.push_back(atof(items[i].c_str()));
    return out;
}

static std::string stem(const std::string& path)
{
    size_t a = path.find_last_of('/');
    a = a == std::string::npos ? 0 : a + 1;
    const size_t b = path.find_last_of('.');
    return path.substr(a, b == std::string::npos || b < a ? std::string::npos : b - a);
}

int main(int argc, char** argv)
{
    cv::CommandLineParser parser(argc, argv, keys);
    parser.about("forestmod_train: meshes -> forestmod model (templates with poses + forest)");
    if (parser.has("help"))
    {
        parser.printMessage();
        return 0;
    }
    const std::vector<std::string> meshes = splitList(parser.get<std::string>("meshes"));
    std::vector<std::string> ids = splitList(parser.get<std::string>("ids"));
    const std::string out = parser.get<std::string>("out");
    const std::string camera = parser.get<std::string>("camera");
    const std::string mods = parser.get<std::string>("modalities");
    const std::vector<double> radii = numbers(parser.get<std::string>("radii"));
    const std::vector<double> inplane = numbers(parser.get<std::string>("inplane"));
    if (!parser.check())
    {
        parser.printErrors();
        return 1;
    }
    if (meshes.empty() || out.empty())
    {
        std::cerr << "forestmod_train: --meshes and --out are required (see --help)\n";
        return 1;
    }
    if (!ids.empty() && ids.size() != meshes.size())
    {
        std::cerr << "forestmod_train: --ids must name one class per mesh\n";
        return 1;
    }
    if (ids.empty())
        for (size_t i = 0; i < meshes.size(); ++i)
            ids.push_back(stem(meshes[i]));
    if (inplane.size() != 3 || radii.empty())
    {
        std::cerr << "forestmod_train: --inplane is min,max,step and --radii a list of distances\n";
        return 1;
    }
    if (mods != "line" && mods != "linemod")
    {
        std::cerr << "forestmod_train: --modalities is line or linemod\n";
        return 1;
    }
    if (cv::forestmod::samples::refuseOutput("forestmod_train", out, parser.has("force")))
        return 1;
    for (size_t i = 0; i < meshes.size(); ++i)
        if (!cv::utils::fs::exists(meshes[i]))
        {
            std::cerr << "forestmod_train: mesh not found: " << meshes[i] << "\n";
            return 1;
        }
    try
    {
        cv::Matx33d K = lmoIntrinsics();
        cv::Size size(640, 480);
        if (!camera.empty())
        {
            cv::FileStorage fs(camera, cv::FileStorage::READ | cv::FileStorage::FORMAT_JSON);
            if (!fs.isOpened())
            {
                std::cerr << "forestmod_train: cannot read " << camera << "\n";
                return 1;
            }
            K = cv::Matx33d((double)fs["fx"], 0, (double)fs["cx"], 0, (double)fs["fy"],
                            (double)fs["cy"], 0, 0, 1);
            size = cv::Size((int)fs["width"], (int)fs["height"]);
        }
        cv::Ptr<cv::forestmod::Detector> detector = mods == "line"
            ? cv::forestmod::getDefaultForestLINE()
            : cv::forestmod::getDefaultForestLINEMOD();
        cv::forestmod::DetectorParams params = detector->getParams();
        params.forest.num_trees = parser.get<int>("trees");
        if (parser.get<double>("fuzzy") >= 0)
            params.forest.fuzzy_margin = (float)parser.get<double>("fuzzy");
        detector->setParams(params);

        cv::forestmod::ViewSampler::Params sp;
        sp.level = parser.get<int>("level");
        sp.min_elevation = parser.get<double>("min_elevation");
        sp.max_elevation = parser.get<double>("max_elevation");
        sp.radii = radii;
        sp.inplane_min = inplane[0];
        sp.inplane_max = inplane[1];
        sp.inplane_step = inplane[2];
        const cv::forestmod::ViewSampler sampler(sp);
        const double scale = parser.get<double>("scale");
        for (size_t i = 0; i < meshes.size(); ++i)
        {
            const cv::forestmod::Mesh mesh = cv::forestmod::Mesh::load(meshes[i], scale);
            const int added = detector->addTemplates(
                mesh, ids[i], sampler, K, size, [&](int done, int total) -> bool {
                    if (done % 20 == 0 || done == total)
                        fprintf(stderr, "\r[%s] %d/%d templates rendered", ids[i].c_str(), done,
                                total);
                    return true;
                });
            fprintf(stderr, "\n%s: %d templates\n", ids[i].c_str(), added);
        }
        fprintf(stderr, "training the forest...\n");
        cv::TickMeter tm;
        tm.start();
        detector->train();
        tm.stop();
        fprintf(stderr, "trained in %.1f ms\n", tm.getTimeMilli());
        for (int g = 0; g < detector->numSearchGroups(); ++g)
        {
            const cv::forestmod::TemplateForest::Statistics st
                = detector->getForest(g)->statistics();
            fprintf(stderr, "search group %d (%d classes): forest %d trees, %d nodes, %d leaves, "
                            "depth %d, %.1f templates per leaf\n", g,
                    (int)detector->getSearchGroupClasses(g).size(), st.trees, st.nodes,
                    st.leaves, st.max_depth, st.mean_leaf_size);
        }
        detector->save(out, parser.has("force"));
        std::cout << "wrote " << out << ": " << detector->numTemplates() << " templates of "
                  << detector->numClasses() << " classes" << std::endl;
    }
    catch (const cv::Exception& e)
    {
        std::cerr << "forestmod_train: " << e.what() << std::endl;
        return 1;
    }
    return 0;
}
