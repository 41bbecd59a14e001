/*
 * A real kernel GPIO chip for the x86 test VM (Debian 12's kernel has no gpio-sim or
 * gpio-mockup). This ACPI table, passed to QEMU with -acpitable, declares an "AMD Promontory"
 * GPIO controller (_HID AMDIF030). Linux binds its in-tree driver gpio-amdpt to it: 8 lines,
 * registers DIRECTION 0x00, INPUTDATA 0x04, OUTPUTDATA 0x08 over the kernel's generic MMIO
 * GPIO library, exposed as /dev/gpiochip0 with the label "AMDIF030:00". The register window
 * is a RAM page the kernel is told to leave alone (memmap=4K$0x10000000), so the driver's
 * writes stay readable there; tests read and write it through /dev/mem (iomem=relaxed) as
 * the pins. Compiled with iasl (acpica-tools) by run_vm_test.sh.
 */
DefinitionBlock ("", "SSDT", 2, "TVEKF", "GPIOPT", 1)
{
    Scope (\_SB)
    {
        Device (GPT0)
        {
            Name (_HID, "AMDIF030")
            Name (_UID, Zero)
            Name (_CRS, ResourceTemplate ()
            {
                Memory32Fixed (ReadWrite, 0x10000000, 0x00001000)
            })
            Method (_STA, 0, NotSerialized)
            {
                Return (0x0F)
            }
        }
    }
}
