!> The one place that knows every scene: makes the scene a configuration asks for.
module mpm_scenes
   use mpm_errors, only: error_t, set_error
   use mpm_config, only: config_t, known_scenes, material_of
   use mpm_scene, only: scene_t
   use mpm_scene_bar, only: bar_init
   use mpm_scene_column, only: column_init
   use mpm_scene_manufactured, only: manufactured_init
   use mpm_scene_composite, only: composite_t, composite_init
   use mpm_scene_impact, only: impact_init
   use mpm_scene_plastic_wave, only: plastic_wave_init
   implicit none
   private
   public :: make_scene

contains

   subroutine make_scene(config, scene, error)
      type(config_t), intent(in) :: config
      class(scene_t), allocatable, intent(out) :: scene
      type(error_t), allocatable, intent(out) :: error
      select case (trim(config%scene_kind))
      case ('vibrating_bar')
         allocate (scene, source=bar_init(config%length, config%youngs_modulus, config%density, &
                                          config%velocity_amplitude, config%mode))
      case ('column')
         allocate (scene, source=column_init(config%length, config%youngs_modulus, config%density, config%gravity, &
                                             static=trim(config%integrator) == 'quasi_static', &
                                             material=material_of(config)))
      case ('manufactured')
         allocate (scene, source=manufactured_init(config%length, config%youngs_modulus, config%density, &
                                                   config%amplitude, config%elements, config%law))
      case ('composite_bar')
         block
            type(composite_t) :: composite
            call composite_init(config, composite, error)
            if (allocated(error)) return
            allocate (scene, source=composite)
         end block
      case ('impact')
         allocate (scene, source=impact_init(config))
      case ('plastic_wave')
         allocate (scene, source=plastic_wave_init(config))
      case default
         call set_error(error, "scene: kind = '"//trim(config%scene_kind)//"' is unknown; allowed: "//known_scenes)
      end select
   end subroutine make_scene
end module mpm_scenes
