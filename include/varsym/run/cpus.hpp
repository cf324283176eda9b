// varsym/run/cpus.hpp: how many CPUs this process may use, for the default number of threads
// (ensembles, sections, a robot's derivatives in optimal control): its affinity mask (taskset,
// a cpuset) and its cgroup's CPU quota (docker --cpus, a Kubernetes CPU limit, systemd's
// CPUQuota), where the machine's core count alone would start more threads than the quota runs.
#pragma once

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#ifdef __linux__
#include <sched.h>
#endif

namespace varsym {

/// The lesser of two CPU limits, 0 standing for none.
inline unsigned least_limit(unsigned a, unsigned b) {
    return a == 0 ? b : b == 0 ? a : std::min(a, b);
}

namespace cpus_detail {

/// The CPUs a quota of `quota` per `period` (both in µs) runs at once, rounded up (at most
/// 2^20); 0: no quota (cgroup v2's "max", v1's -1, or unreadable values).
inline unsigned quota_cpus(double quota, double period) {
    if (!(quota > 0.0) || !(period > 0.0) || !std::isfinite(quota / period)) return 0;
    return static_cast<unsigned>(std::clamp(std::ceil(quota / period - 1e-9), 1.0, 1048576.0));
}

/// The least quota among a cgroup directory `dir` (under the hierarchy's mount `mount`) and its
/// ancestors up to the mount: a limit anywhere above applies too. 0: none found.
template <class Read>
unsigned least_quota(const std::string& mount, std::string dir, Read read) {
    unsigned least = 0;
    for (;;) {
        least = least_limit(least, read(mount + dir));
        if (dir.empty() || dir == "/") return least;
        const auto slash = dir.find_last_of('/');
        dir = slash == std::string::npos ? std::string() : dir.substr(0, slash);
    }
}

inline unsigned v2_quota(const std::string& dir) {
    std::ifstream f(dir + "/cpu.max");
    std::string quota;
    double period = 0.0;
    if (!(f >> quota >> period) || quota == "max") return 0;
    std::istringstream q(quota);
    double value = 0.0;
    return q >> value ? quota_cpus(value, period) : 0;
}

inline unsigned v1_quota(const std::string& dir) {
    std::ifstream q(dir + "/cpu.cfs_quota_us"), p(dir + "/cpu.cfs_period_us");
    double quota = 0.0, period = 0.0;
    return q >> quota && p >> period ? quota_cpus(quota, period) : 0;
}

} // namespace cpus_detail

/// The CPU quota of this process's cgroup (v2: cpu.max; v1: cpu.cfs_quota_us over
/// cpu.cfs_period_us, in the hierarchy mounted under its controllers' names, or "cpu,cpuacct"
/// or "cpu"), its ancestors' included, as a whole number of CPUs rounded up; 0 where there is
/// none. `root` is the file system's root ("/"; a test's directory in the tests):
/// proc/self/cgroup names the cgroup, sys/fs/cgroup holds the hierarchies.
inline unsigned cgroup_cpu_limit(const std::string& root = "/") {
    std::ifstream groups(root + "proc/self/cgroup");
    const std::string mount = root + "sys/fs/cgroup";
    unsigned least = 0;
    std::string line;
    while (std::getline(groups, line)) {
        // "0::/path" (v2), "4:cpu,cpuacct:/path" (v1).
        const auto a = line.find(':'), b = a == std::string::npos ? a : line.find(':', a + 1);
        if (b == std::string::npos) continue;
        const std::string controllers = line.substr(a + 1, b - a - 1), path = line.substr(b + 1);
        if (line.compare(0, a, "0") == 0 && controllers.empty()) {
            least =
                least_limit(least, cpus_detail::least_quota(mount, path, cpus_detail::v2_quota));
            continue;
        }
        std::stringstream list(controllers);
        for (std::string c; std::getline(list, c, ',');) {
            if (c != "cpu") continue;
            for (const std::string& name :
                 {controllers, std::string("cpu,cpuacct"), std::string("cpu")})
                least = least_limit(least, cpus_detail::least_quota(mount + "/" + name, path,
                                                                    cpus_detail::v1_quota));
        }
    }
    return least;
}

/// The CPUs of this process's affinity mask (taskset, a cpuset; elsewhere than Linux the
/// machine's), at least 1.
inline unsigned affinity_cpus() {
    unsigned n = std::thread::hardware_concurrency();
#ifdef __linux__
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) == 0) n = static_cast<unsigned>(CPU_COUNT(&set));
#endif
    return std::max(1U, n);
}

/// The machine's online CPUs, at most this process's cgroup CPU quota, at least 1: what the
/// processes of one machine (MPI ranks) share.
inline unsigned machine_cpus() {
    return least_limit(std::max(1U, std::thread::hardware_concurrency()), cgroup_cpu_limit());
}

/// The CPUs this process may use: its affinity mask's, at most its cgroup's CPU quota
/// (cgroup_cpu_limit), at least 1.
inline unsigned available_cpus() {
    return least_limit(affinity_cpus(), cgroup_cpu_limit());
}

} // namespace varsym
