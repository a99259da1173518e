/* The Uno's pins (ATmega328P, 16 MHz). Fixed: the simavr harness and
 * docs/firmware.md are written against this map.
 *
 *   D0/D1  UART0, the link (115200 8N1)
 *   D5  OC0B  left PWM (L298N ENA)    D4  PD4  IN1    D7  PD7  IN2
 *   D6  OC0A  right PWM (L298N ENB)   D8  PB0  IN3    D12 PB4  IN4
 *   A0 PC0 left A   A1 PC1 left B   A2 PC2 right A   A3 PC3 right B
 *   A4 PC4 arm limit   A5 PC5 jaw limit (inputs, pull-ups, active low)
 *   D9 PB1 arm motor   D10 PB2 gripper   D11 PB3 beeper   D13 PB5 LED
 *   D2 PD2 arm down    D3 PD3 gripper close (direction relays; added)
 */
#ifndef RCL_PINS_UNO_H
#define RCL_PINS_UNO_H
#include <avr/io.h>

#define BOARD_NAME "Uno"

#define L_PWM_DDR DDRD
#define L_PWM_PORT PORTD
#define L_PWM_BIT 5
#define L_OCR OCR0B
#define L_COM COM0B1
#define L_IN1_DDR DDRD
#define L_IN1_PORT PORTD
#define L_IN1_BIT 4
#define L_IN2_DDR DDRD
#define L_IN2_PORT PORTD
#define L_IN2_BIT 7

#define R_PWM_DDR DDRD
#define R_PWM_PORT PORTD
#define R_PWM_BIT 6
#define R_OCR OCR0A
#define R_COM COM0A1
#define R_IN1_DDR DDRB
#define R_IN1_PORT PORTB
#define R_IN1_BIT 0
#define R_IN2_DDR DDRB
#define R_IN2_PORT PORTB
#define R_IN2_BIT 4

/* encoders and limit switches: one port, one pin-change interrupt */
#define SENSE_DDR DDRC
#define SENSE_PORT PORTC
#define SENSE_PIN PINC
#define SENSE_PCMSK PCMSK1
#define SENSE_PCIE PCIE1
#define SENSE_VECT PCINT1_vect
#define ENC_MASK 0x0F               /* PC0..PC3 */
#define LIMIT_ARM_BIT 4
#define LIMIT_JAW_BIT 5

#define AUX_DDR DDRB
#define AUX_PORT_REG PORTB
#define ARM_BIT 1
#define GRIP_BIT 2
#define BEEP_DDR DDRB
#define BEEP_PORT PORTB
#define BEEP_BIT 3
#define DIR_DDR DDRD
#define DIR_PORT PORTD
#define ARM_DOWN_BIT 2
#define GRIP_CLOSE_BIT 3
#define LED_DDR DDRB
#define LED_PORT PORTB
#define LED_BIT 5

#define UART_RX_VECT USART_RX_vect
#define UART_UDRE_VECT USART_UDRE_vect
#endif
