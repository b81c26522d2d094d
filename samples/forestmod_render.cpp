// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Renders a mesh into a BOP-style training folder (one "scene" holding every template view):
//   OUT/rgb/000000.png           colour (BGR PNG)
//   OUT/depth/000000.png         16-bit depth, mm (depth_scale 1.0), 0 = background
//   OUT/mask/000000_000000.png   object mask (also mask_visib/: a template has no occluder)
//   OUT/scene_gt.json            {"0": [{"cam_R_m2c": [...9], "cam_t_m2c": [...3], "obj_id": N}], ...}
//   OUT/scene_camera.json        {"0": {"cam_K": [...9], "depth_scale": 1.0}, ...}
//   OUT/scene_gt_info.json       bbox_obj, bbox_visib, px_count_*, visib_fract as bop_toolkit
//   OUT/view_info.json           (forestmod) radius, elevation, azimuth, in-plane of each view

#include <opencv2/core.hpp>
#include <opencv2/core/utils/filesystem.hpp>
#include <opencv2/forestmod.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "sample_utils.hpp"
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

static const char* keys
    = "{help h usage ?  |        | print this message }"
      "{mesh            |        | mesh file (PLY, OBJ, STL, ... anything assimp reads) }"
      "{out             |        | output folder (created; must be empty unless --force) }"
      "{scale           | 1      | file units -> mm (1000 for meshes in metres) }"
      "{obj_id          | -1     | obj_id written to scene_gt.json (-1: from a file name "
      "obj_NNNNNN.*, else 1) }"
      "{camera          |        | BOP camera.json with fx, fy, cx, cy, width, height (overrides "
      "the values below) }"
      "{fx              | 572.4114 | focal length x (px); defaults: LM/LM-O Primesense }"
      "{fy              | 573.57043 | focal length y (px) }"
      "{cx              | 325.2611 | principal point x (px) }"
      "{cy              | 242.04899 | principal point y (px) }"
      "{width           | 640    | image width }"
      "{height          | 480    | image height }"
      "{level           | 2      | icosahedron subdivisions (2: ~15 deg between views) }"
      "{radii           | 650,750,850,950,1050,1150 | camera distances (mm), comma separated }"
      "{min_elevation   | 0      | lowest elevation (deg) }"
      "{max_elevation   | 90     | highest elevation (deg) }"
      "{inplane_min     | -45    | in-plane rotation range start (deg) }"
      "{inplane_max     | 45     | in-plane rotation range end (deg) }"
      "{inplane_step    | 15     | in-plane rotation step (deg) }"
      "{coarse          |        | quick set: level 0, radius 800, no in-plane rotation (6 views) }"
      "{limit           | 0      | stop after this many views (0 = all) }"
      "{force           |        | write into a non-empty output folder (the PNGs of rgb/, depth/, "
      "mask/, mask_visib/ and the JSON files of a previous run are deleted first) }";

static std::string joinNumbers(const double* v, int n)
{
    std::ostringstream s;
    s.precision(10);
    s << "[";
    for (int i = 0; i < n; ++i)
        s << (i ? ", " : "") << v[i];
    s << "]";
    return s.str();
}

static bool parseRadii(const std::string& text, std::vector<double>& radii)
{
    radii.clear();
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ','))
    {
        char* end = 0;
        const double r = std::strtod(item.c_str(), &end);
        if (end == item.c_str() || !(r > 0))
            return false;
        radii.push_back(r);
    }
    return !radii.empty();
}

static int objIdFromName(const std::string& path)
{
    const size_t slash = path.find_last_of("/\\");
    const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
    int id = 0;
    if (std::sscanf(name.c_str(), "obj_%d.", &id) == 1 && id > 0)
        return id;
    return 1;
}

int main(int argc, char** argv)
{
    cv::CommandLineParser parser(argc, argv, keys);
    parser.about("forestmod_render: renders a mesh from the views of a cv::forestmod::ViewSampler "
                 "into a BOP-style training folder (rgb/, depth/, mask/, scene_gt.json, "
                 "scene_camera.json, scene_gt_info.json)");
    if (parser.has("help"))
    {
        parser.printMessage();
        return 0;
    }
    const std::string mesh_path = parser.get<std::string>("mesh");
    const std::string out = parser.get<std::string>("out");
    const double scale = parser.get<double>("scale");
    int obj_id = parser.get<int>("obj_id");
    const std::string camera = parser.get<std::string>("camera");
    double fx = parser.get<double>("fx"), fy = parser.get<double>("fy");
    double cx = parser.get<double>("cx"), cy = parser.get<double>("cy");
    int width = parser.get<int>("width"), height = parser.get<int>("height");
    cv::forestmod::ViewSampler::Params sp;
    sp.level = parser.get<int>("level");
    const std::string radii = parser.get<std::string>("radii");
    sp.min_elevation = parser.get<double>("min_elevation");
    sp.max_elevation = parser.get<double>("max_elevation");
    sp.inplane_min = parser.get<double>("inplane_min");
    sp.inplane_max = parser.get<double>("inplane_max");
    sp.inplane_step = parser.get<double>("inplane_step");
    const int limit = parser.get<int>("limit");
    const bool force = parser.has("force");
    if (!parser.check())
    {
        parser.printErrors();
        return 1;
    }
    if (mesh_path.empty() || out.empty())
    {
        std::cerr << "forestmod_render: --mesh and --out are required (see --help)\n";
        return 1;
    }
    if (!cv::utils::fs::exists(mesh_path) || cv::utils::fs::isDirectory(mesh_path))
    {
        std::cerr << "forestmod_render: mesh file '" << mesh_path << "' not found\n";
        return 1;
    }
    if (!parseRadii(radii, sp.radii))
    {
        std::cerr << "forestmod_render: --radii must be positive numbers separated by commas, got '"
                  << radii << "'\n";
        return 1;
    }
    if (parser.has("coarse"))
        sp = cv::forestmod::ViewSampler::Params::coarse();
    if (obj_id < 0)
        obj_id = objIdFromName(mesh_path);
    if (!camera.empty())
    {
        cv::FileStorage fs(camera, cv::FileStorage::READ);
        if (!fs.isOpened() || fs["fx"].empty() || fs["width"].empty())
        {
            std::cerr << "forestmod_render: cannot read fx, fy, cx, cy, width, height from '"
                      << camera << "'\n";
            return 1;
        }
        fx = (double)fs["fx"];
        fy = (double)fs["fy"];
        cx = (double)fs["cx"];
        cy = (double)fs["cy"];
        width = (int)fs["width"];
        height = (int)fs["height"];
    }
    if (cv::forestmod::samples::isDanglingSymlink(out))
    {
        std::cerr << "forestmod_render: '" << out << "' is a dangling symbolic link; it is not "
                  << "written through (remove it or choose another folder)\n";
        return 1;
    }
    if (cv::utils::fs::exists(out))
    {
        if (!cv::utils::fs::isDirectory(out))
        {
            std::cerr << "forestmod_render: '" << out << "' exists and is not a folder\n";
            return 1;
        }
        std::vector<cv::String> entries;
        cv::utils::fs::glob(out, "*", entries, false, true);
        if (!entries.empty() && !force)
        {
            std::cerr << "forestmod_render: output folder '" << out
                      << "' is not empty; pass --force to write into it\n";
            return 1;
        }
        if (!entries.empty())
        {
            // --force: remove a previous run's output (PNGs in our four folders, our JSON files)
            // so that no stale view outlives the new JSON; anything else is left alone
            const char* dirs[] = { "rgb", "depth", "mask", "mask_visib" };
            for (int i = 0; i < 4; ++i)
            {
                std::vector<cv::String> pngs;
                if (cv::utils::fs::isDirectory(out + "/" + dirs[i]))
                    cv::utils::fs::glob(out + "/" + dirs[i], "*.png", pngs, false, false);
                for (size_t k = 0; k < pngs.size(); ++k)
                    std::remove(pngs[k].c_str());
            }
            const char* jsons[] = { "scene_gt.json", "scene_camera.json", "scene_gt_info.json",
                                    "view_info.json" };
            for (int i = 0; i < 4; ++i)
                std::remove((out + "/" + jsons[i]).c_str());
        }
    }

    try
    {
        const cv::forestmod::ViewSampler sampler(sp);
        const cv::forestmod::Mesh mesh = cv::forestmod::Mesh::load(mesh_path, scale);
        const cv::Matx33d K(fx, 0, cx, 0, fy, cy, 0, 0, 1);
        const int total = limit > 0 ? std::min(limit, sampler.size()) : sampler.size();
        const char* subdirs[] = { "rgb", "depth", "mask", "mask_visib" };
        for (int i = 0; i < 4; ++i)
            if (!cv::utils::fs::createDirectories(out + "/" + subdirs[i]))
            {
                std::cerr << "forestmod_render: cannot create " << out << "/" << subdirs[i] << "\n";
                return 1;
            }
        const cv::Point3f c = mesh.center();
        std::cerr << "forestmod_render: " << mesh_path << ": " << mesh.vertices.size()
                  << " vertices, " << mesh.faces.size() << " faces, diameter " << mesh.diameter()
                  << " mm, centre (" << c.x << ", " << c.y << ", " << c.z << "); " << total
                  << " views at " << width << "x" << height << " -> " << out << "\n";

        std::ostringstream gt, cam, info, views;
        gt << "{";
        cam << "{";
        info << "{";
        views << "{";
        const int64 t0 = cv::getTickCount();
        bool write_failed = false;
        double last_print = -1.0;
        int bad_view = -1, bad_px = 0;
        auto sink = [&](const cv::forestmod::TemplateView& v, int done, int) -> bool {
            // a view without an object pixel, or covered by the object, is not a template
            // view: a degenerate mesh, a wrong --scale or radii that do not fit the mesh
            const int px = cv::countNonZero(v.mask);
            if (px == 0 || px == (int)v.mask.total())
            {
                bad_view = v.view_id;
                bad_px = px;
                return false;
            }
            const std::string id = cv::format("%06d", v.view_id);
            const std::string mask_name = cv::format("%06d_%06d.png", v.view_id, 0);
            if (!cv::imwrite(out + "/rgb/" + id + ".png", v.color)
                || !cv::imwrite(out + "/depth/" + id + ".png", v.depth)
                || !cv::imwrite(out + "/mask/" + mask_name, v.mask)
                || !cv::imwrite(out + "/mask_visib/" + mask_name, v.mask))
            {
                write_failed = true;
                return false;
            }
            const char* sep = v.view_id ? ",\n " : "\n ";
            gt << sep << "\"" << v.view_id << "\": [{\"cam_R_m2c\": " << joinNumbers(v.R.val, 9)
               << ", \"cam_t_m2c\": " << joinNumbers(v.t.val, 3) << ", \"obj_id\": " << obj_id
               << "}]";
            cam << sep << "\"" << v.view_id << "\": {\"cam_K\": " << joinNumbers(v.K.val, 9)
                << ", \"depth_scale\": 1.0}";
            // BOP's box: (xmin, ymin, xmax - xmin, ymax - ymin); the view is centred on the
            // object, so the whole silhouette is in the image unless the object is very close
            const cv::Rect& b = v.bbox;
            const std::string box = b.area() > 0 ? cv::format("[%d, %d, %d, %d]", b.x, b.y,
                                                              b.width - 1, b.height - 1)
                                                 : std::string("[-1, -1, -1, -1]");
            info << sep << "\"" << v.view_id << "\": [{\"bbox_obj\": " << box
                 << ", \"bbox_visib\": " << box << ", \"px_count_all\": " << px
                 << ", \"px_count_valid\": " << px << ", \"px_count_visib\": " << px
                 << ", \"visib_fract\": " << (px > 0 ? "1.0" : "0.0") << "}]";
            views << sep << "\"" << v.view_id << "\": {\"radius\": " << v.radius
                  << ", \"elevation\": " << v.elevation << ", \"azimuth\": " << v.azimuth
                  << ", \"inplane\": " << v.inplane << ", \"view_index\": " << v.view_index
                  << ", \"radius_index\": " << v.radius_index << ", \"inplane_index\": "
                  << v.inplane_index << "}";
            // progress bar, redrawn at most 5 times a second
            const double secs = (cv::getTickCount() - t0) / cv::getTickFrequency();
            if (secs < last_print + 0.2 && done < total)
                return true;
            last_print = secs;
            const int bar = 40 * done / total;
            std::fprintf(stderr, "\r[%s%s] %d/%d  %.1f views/s ",
                         std::string(bar, '=').c_str(), std::string(40 - bar, ' ').c_str(), done,
                         total, secs > 0 ? done / secs : 0.0);
            return done < total;
        };
        cv::forestmod::renderTemplates(mesh, sampler, K, cv::Size(width, height), sink);
        std::fprintf(stderr, "\n");
        if (bad_view >= 0)
        {
            std::cerr << "forestmod_render: view " << bad_view << ": "
                      << (bad_px == 0 ? "no pixel of the object is visible"
                                      : "the object covers the whole frame")
                      << " (a degenerate mesh, a wrong --scale or --radii that do not fit the "
                      << "mesh's size); stopped, the output in " << out << " is incomplete\n";
            return 1;
        }
        if (write_failed)
        {
            std::cerr << "forestmod_render: cannot write images into " << out << "\n";
            return 1;
        }
        gt << "\n}\n";
        cam << "\n}\n";
        info << "\n}\n";
        views << "\n}\n";
        const std::pair<std::string, std::string> files[] = {
            std::make_pair(std::string("scene_gt.json"), gt.str()),
            std::make_pair(std::string("scene_camera.json"), cam.str()),
            std::make_pair(std::string("scene_gt_info.json"), info.str()),
            std::make_pair(std::string("view_info.json"), views.str())
        };
        for (int i = 0; i < 4; ++i)
        {
            std::ofstream f((out + "/" + files[i].first).c_str());
            f << files[i].second;
            if (!f.good())
            {
                std::cerr << "forestmod_render: cannot write " << out << "/" << files[i].first << "\n";
                return 1;
            }
        }
        const double secs = (cv::getTickCount() - t0) / cv::getTickFrequency();
        std::cout << "wrote " << total << " views of obj_id " << obj_id << " to " << out << " in "
                  << cv::format("%.1f", secs) << " s" << std::endl;
    }
    catch (const cv::Exception& e)
    {
        std::cerr << "\nforestmod_render: " << e.err << std::endl;
        return 1;
    }
    return 0;
}
