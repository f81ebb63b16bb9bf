#include "cl/kernel.h"

#include "util/error.h"

namespace wp::ocl {

Kernel::Kernel(const Program& program, const std::string& entry, std::string label, std::size_t local)
    : kernel_(program.kernel(entry)), entry_(entry), label_(label.empty() ? entry : std::move(label)),
      file_(program.file), local_(local) {
    arg_count_ = kernel_.getInfo<CL_KERNEL_NUM_ARGS>();
}

void Kernel::check_arg_count(std::size_t given) const {
    if (given != arg_count_)
        fail("launcher of kernel '{}' (kernels/{}) passes {} arguments, but the kernel takes {}",
             entry_, file_, given, arg_count_);
}

}  // namespace wp::ocl
