// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// libFuzzer target: forestmod::Mesh::load on PLY files (inputs that start with "ply"), then the
// mesh's geometry helpers.
// Every outcome but a cv::Exception or a valid mesh is a finding.

#include "fuzz_common.hpp"

#include <opencv2/core.hpp>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/forestmod.hpp>

#include <cctype>
#include <cstring>

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    static const std::string path = forestmod_fuzz::inputPath(".ply");
    // PLY only (forestmod's meshes, BOP's format): other content goes straight to assimp's other
    // readers, whose hangs and aborts are assimp's (Debian's build keeps its assertions on)
    if (size < 4 || std::memcmp(data, "ply", 3) != 0 || !std::isspace(data[3]))
        return 0;
    if (!forestmod_fuzz::writeInput(path, data, size))
        return 0;
    try
    {
        const cv::forestmod::Mesh mesh = cv::forestmod::Mesh::load(path);
        mesh.validate();
        if (mesh.vertices.size() < 5000) // the exact diameter is quadratic at worst
            (void)mesh.diameter();
        (void)mesh.center();
    }
    catch (const cv::Exception&)
    {
    }
    return 0;
}
