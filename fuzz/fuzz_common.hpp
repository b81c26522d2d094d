// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Shared by the fuzz targets: the loaders read files, so each input is written to a file of
// this process first (on /dev/shm when there is one: no disk traffic per execution).

#ifndef FORESTMOD_FUZZ_COMMON_HPP
#define FORESTMOD_FUZZ_COMMON_HPP

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <unistd.h>

namespace forestmod_fuzz {

inline std::string inputPath(const char* suffix)
{
    const char* dir = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
    return std::string(dir) + "/forestmod_fuzz_" + std::to_string((long long)getpid()) + suffix;
}

inline bool writeInput(const std::string& path, const uint8_t* data, size_t size)
{
    FILE* f = std::fopen(path.c_str(), "wb");
    if (!f)
        return false;
    const bool ok = std::fwrite(data, 1, size, f) == size;
    return std::fclose(f) == 0 && ok;
}

} // namespace forestmod_fuzz

#endif
