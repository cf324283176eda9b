// varsym/run/cpus.hpp: the cgroup CPU quota read from a made-up file system (cgroup v2 and v1,
// quotas above the process's own cgroup, none), and available_cpus() against the affinity mask.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#ifdef __linux__
#include <sched.h>
#endif

#include "varsym/run/cpus.hpp"

namespace {

/// A directory standing for "/": files written under it by path.
class fake_root {
  public:
    explicit fake_root(const std::string& name)
        : dir_(std::filesystem::path(testing::TempDir()) /
               ("varsym_cpus_" + name + "_" + std::to_string(getpid()))) {
        std::filesystem::remove_all(dir_);
    }
    fake_root(const fake_root&) = delete;
    fake_root& operator=(const fake_root&) = delete;
    ~fake_root() {
        std::error_code ignored;
        std::filesystem::remove_all(dir_, ignored);
    }
    void write(const std::string& path, const std::string& text) const {
        const auto file = dir_ / path;
        std::filesystem::create_directories(file.parent_path());
        std::ofstream(file) << text;
    }
    [[nodiscard]] std::string root() const { return dir_.string() + "/"; }

  private:
    std::filesystem::path dir_;
};

} // namespace

TEST(Cpus, CgroupV2QuotaIsTheLeastAlongTheCgroupsAncestorsRoundedUp) {
    fake_root f("v2");
    f.write("proc/self/cgroup", "0::/user.slice/job\n");
    EXPECT_EQ(varsym::cgroup_cpu_limit(f.root()), 0U); // no cpu.max anywhere: no quota
    f.write("sys/fs/cgroup/user.slice/job/cpu.max", "max 100000\n");
    EXPECT_EQ(varsym::cgroup_cpu_limit(f.root()), 0U); // "max": none
    f.write("sys/fs/cgroup/user.slice/job/cpu.max", "250000 100000\n");
    EXPECT_EQ(varsym::cgroup_cpu_limit(f.root()), 3U); // 2.5 CPUs: 3 threads
    f.write("sys/fs/cgroup/user.slice/cpu.max", "150000 100000\n");
    EXPECT_EQ(varsym::cgroup_cpu_limit(f.root()), 2U); // the parent's is less
    f.write("sys/fs/cgroup/cpu.max", "50000 100000\n");
    EXPECT_EQ(varsym::cgroup_cpu_limit(f.root()), 1U); // half a CPU: still one thread
    f.write("sys/fs/cgroup/cpu.max", "100000 0\n");    // a broken root file is no quota
    EXPECT_EQ(varsym::cgroup_cpu_limit(f.root()), 2U);
}

TEST(Cpus, CgroupV1QuotaOfTheCpuControllerAlone) {
    fake_root f("v1");
    f.write("proc/self/cgroup", "4:memory:/box\n3:cpu,cpuacct:/box\n0::/\n");
    f.write("sys/fs/cgroup/cpu,cpuacct/box/cpu.cfs_quota_us", "-1\n");
    f.write("sys/fs/cgroup/cpu,cpuacct/box/cpu.cfs_period_us", "100000\n");
    EXPECT_EQ(varsym::cgroup_cpu_limit(f.root()), 0U); // -1: none
    f.write("sys/fs/cgroup/cpu,cpuacct/box/cpu.cfs_quota_us", "400000\n");
    EXPECT_EQ(varsym::cgroup_cpu_limit(f.root()), 4U);
    // The memory controller's directory is not read for a CPU quota.
    f.write("sys/fs/cgroup/memory/box/cpu.cfs_quota_us", "100000\n");
    f.write("sys/fs/cgroup/memory/box/cpu.cfs_period_us", "100000\n");
    EXPECT_EQ(varsym::cgroup_cpu_limit(f.root()), 4U);
    // A mount of its own ("cpu"), as on hosts that split the two controllers.
    f.write("sys/fs/cgroup/cpu/box/cpu.cfs_quota_us", "300000\n");
    f.write("sys/fs/cgroup/cpu/box/cpu.cfs_period_us", "100000\n");
    EXPECT_EQ(varsym::cgroup_cpu_limit(f.root()), 3U);
}

TEST(Cpus, AvailableCpusIsTheAffinityMaskAtMostTheQuota) {
    EXPECT_EQ(varsym::least_limit(0, 3), 3U); // 0: no limit
    EXPECT_EQ(varsym::least_limit(5, 0), 5U);
    EXPECT_EQ(varsym::least_limit(5, 3), 3U);
    unsigned affinity = std::thread::hardware_concurrency();
#ifdef __linux__
    cpu_set_t set;
    CPU_ZERO(&set);
    ASSERT_EQ(sched_getaffinity(0, sizeof set, &set), 0);
    affinity = static_cast<unsigned>(CPU_COUNT(&set));
#endif
    const unsigned quota = varsym::cgroup_cpu_limit();
    const unsigned expected = std::max(1U, quota == 0 ? affinity : std::min(affinity, quota));
    EXPECT_EQ(varsym::available_cpus(), expected);
}
