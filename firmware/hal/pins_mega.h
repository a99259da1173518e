/* The Mega's pins (ATmega2560, 16 MHz). Timer 0's PWM pins on the Mega
 * are D4 (OC0B) and D13 (OC0A), so the link LED moves to D31.
 *
 *   D0/D1  UART0, the link (115200 8N1, the USB serial port)
 *   D4  OC0B  left PWM (ENA)    D22 PA0 IN1    D23 PA1 IN2
 *   D13 OC0A  right PWM (ENB)   D24 PA2 IN3    D25 PA3 IN4
 *   A8 PK0 left A   A9 PK1 left B   A10 PK2 right A   A11 PK3 right B
 *   A12 PK4 arm limit   A13 PK5 jaw limit (pull-ups, active low)
 *   D26 PA4 arm motor   D27 PA5 arm down   D28 PA6 gripper
 *   D29 PA7 gripper close   D30 PC7 beeper   D31 PC6 LED
 */
#ifndef RCL_PINS_MEGA_H
#define RCL_PINS_MEGA_H
#include <avr/io.h>

#define BOARD_NAME "Mega"

#define L_PWM_DDR DDRG
#define L_PWM_PORT PORTG
#define L_PWM_BIT 5
#define L_OCR OCR0B
#define L_COM COM0B1
#define L_IN1_DDR DDRA
#define L_IN1_PORT PORTA
#define L_IN1_BIT 0
#define L_IN2_DDR DDRA
#define L_IN2_PORT PORTA
#define L_IN2_BIT 1

#define R_PWM_DDR DDRB
#define R_PWM_PORT PORTB
#define R_PWM_BIT 7
#define R_OCR OCR0A
#define R_COM COM0A1
#define R_IN1_DDR DDRA
#define R_IN1_PORT PORTA
#define R_IN1_BIT 2
#define R_IN2_DDR DDRA
#define R_IN2_PORT PORTA
#define R_IN2_BIT 3

#define SENSE_DDR DDRK
#define SENSE_PORT PORTK
#define SENSE_PIN PINK
#define SENSE_PCMSK PCMSK2
#define SENSE_PCIE PCIE2
#define SENSE_VECT PCINT2_vect
#define ENC_MASK 0x0F
#define LIMIT_ARM_BIT 4
#define LIMIT_JAW_BIT 5

#define AUX_DDR DDRA
#define AUX_PORT_REG PORTA
#define ARM_BIT 4
#define GRIP_BIT 6
#define DIR_DDR DDRA
#define DIR_PORT PORTA
#define ARM_DOWN_BIT 5
#define GRIP_CLOSE_BIT 7
#define BEEP_DDR DDRC
#define BEEP_PORT PORTC
#define BEEP_BIT 7
#define LED_DDR DDRC
#define LED_PORT PORTC
#define LED_BIT 6

#define UART_RX_VECT USART0_RX_vect
#define UART_UDRE_VECT USART0_UDRE_vect
#endif
