!> The code version written into every output file (keep in step with fpm.toml).
module mpm_version
   implicit none
   private
   public :: code_version
   character(len=*), parameter :: code_version = 'mpm1d 0.1.0'
end module mpm_version
